// A move-only owner of one mmap()ed region (a V4L2 capture buffer), unmapped on destruction.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>

#include <sys/mman.h>

namespace lumar {

class MappedRegion {
public:
    MappedRegion() = default;
    MappedRegion(void* address, size_t length) : address_(address), length_(length) {}
    MappedRegion(const MappedRegion&) = delete;
    MappedRegion& operator=(const MappedRegion&) = delete;
    MappedRegion(MappedRegion&& other) noexcept
        : address_(std::exchange(other.address_, nullptr)), length_(std::exchange(other.length_, 0))
    {
    }
    MappedRegion& operator=(MappedRegion&& other) noexcept
    {
        if (this != &other) {
            reset();
            address_ = std::exchange(other.address_, nullptr);
            length_ = std::exchange(other.length_, 0);
        }
        return *this;
    }
    ~MappedRegion() { reset(); }

    [[nodiscard]] const uint8_t* data() const { return static_cast<const uint8_t*>(address_); }
    [[nodiscard]] size_t size() const { return length_; }

    void reset()
    {
        if (address_ != nullptr) {
            ::munmap(address_, length_);
            address_ = nullptr;
            length_ = 0;
        }
    }

private:
    void* address_ = nullptr;
    size_t length_ = 0;
};

} // namespace lumar
