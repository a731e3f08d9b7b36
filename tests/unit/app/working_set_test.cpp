// dropCleanFilePages: a read-only file mapping leaves the resident set and reads the same
// bytes again; a mapping holding a page copied on write keeps it.
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include "working_set.h"

namespace lumar {
namespace {

constexpr size_t kPages = 256;

// The resident bytes of the mapping that starts at `start`, from /proc/self/smaps.
size_t residentBytesAt(const void* start)
{
    std::ifstream smaps("/proc/self/smaps");
    std::string line;
    bool inside = false;
    while (std::getline(smaps, line)) {
        uintptr_t from = 0, to = 0;
        if (std::sscanf(line.c_str(), "%lx-%lx ", &from, &to) == 2 && line.find(" kB") == std::string::npos)
            inside = from == reinterpret_cast<uintptr_t>(start);
        else if (inside && line.starts_with("Rss:")) {
            std::istringstream in(line.substr(4));
            size_t kb = 0;
            in >> kb;
            return kb * 1024;
        }
    }
    ADD_FAILURE() << "no mapping at " << start;
    return 0;
}

class MappedFile : public ::testing::Test {
protected:
    void SetUp() override
    {
        page_ = size_t(sysconf(_SC_PAGESIZE));
        path_ = std::filesystem::temp_directory_path() / ("lumar_working_set_" + std::to_string(getpid()));
        std::vector<uint8_t> bytes(kPages * page_);
        for (size_t i = 0; i < bytes.size(); ++i)
            bytes[i] = uint8_t(i * 7 + i / page_);
        std::ofstream(path_, std::ios::binary)
            .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
        expected_ = bytes;
        fd_ = open(path_.c_str(), O_RDONLY);
        ASSERT_GE(fd_, 0);
        // Written back, as a library's file is: a page the cache still has to write counts as
        // dirty, and a dirty page is never dropped.
        ASSERT_EQ(fsync(fd_), 0);
    }
    void TearDown() override
    {
        if (fd_ >= 0)
            close(fd_);
        std::filesystem::remove(path_);
    }
    // Maps the file privately and reads every page, so all of them are resident.
    uint8_t* mapAndTouch(int protection)
    {
        void* p = mmap(nullptr, kPages * page_, protection, MAP_PRIVATE, fd_, 0);
        EXPECT_NE(p, MAP_FAILED);
        auto* bytes = static_cast<uint8_t*>(p);
        unsigned sum = 0;
        for (size_t i = 0; i < kPages * page_; i += page_)
            sum += *static_cast<volatile uint8_t*>(bytes + i);
        (void)sum;
        return bytes;
    }

    size_t page_ = 4096;
    std::filesystem::path path_;
    std::vector<uint8_t> expected_;
    int fd_ = -1;
};

TEST_F(MappedFile, ReadOnlyPagesLeaveTheResidentSetAndReadTheSameBytes)
{
    uint8_t* bytes = mapAndTouch(PROT_READ);
    ASSERT_EQ(residentBytesAt(bytes), kPages * page_);
    EXPECT_GE(dropCleanFilePages(), kPages * page_);
    EXPECT_EQ(residentBytesAt(bytes), 0u);
    EXPECT_EQ(std::memcmp(bytes, expected_.data(), expected_.size()), 0);
    munmap(bytes, kPages * page_);
}

TEST_F(MappedFile, AMappingWithAPageCopiedOnWriteIsKept)
{
    // As the dynamic loader leaves a library's relocated constants: written, then read-only.
    uint8_t* bytes = mapAndTouch(PROT_READ | PROT_WRITE);
    bytes[3 * page_ + 5] ^= 0xff;
    ASSERT_EQ(mprotect(bytes, kPages * page_, PROT_READ), 0);
    expected_[3 * page_ + 5] ^= 0xff;
    (void)dropCleanFilePages();
    EXPECT_EQ(residentBytesAt(bytes), kPages * page_);
    EXPECT_EQ(std::memcmp(bytes, expected_.data(), expected_.size()), 0);
    munmap(bytes, kPages * page_);
}

} // namespace
} // namespace lumar
