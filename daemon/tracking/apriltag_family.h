// AprilTag 3 tag families created by name, owned through RAII. Each family has its own
// create/destroy pair in the C API; this maps the names lumar accepts onto them.
#pragma once

#include <memory>
#include <string>

struct apriltag_family;

namespace lumar {

struct AprilTagFamilyDeleter {
    void (*destroy)(apriltag_family*) = nullptr;
    void operator()(apriltag_family* family) const
    {
        if (family && destroy)
            destroy(family);
    }
};
using AprilTagFamilyPtr = std::unique_ptr<apriltag_family, AprilTagFamilyDeleter>;

// Throws InputError "unknown tag family 'x'" for a name the library does not provide.
AprilTagFamilyPtr createAprilTagFamily(const std::string& name);

// The bytes of the decode table libapriltag builds for `family` with `bits` correctable bit
// errors (3 slots of 16 bytes per code variant, its own sizing; see the .cpp).
double decodeTableBytes(const apriltag_family& family, int bits);

// How many bit errors the detector may correct for `family`: the library's default of 2
// where its decode table stays small, fewer for the large families (see the .cpp).
int correctableBitsFor(const apriltag_family& family);

} // namespace lumar
