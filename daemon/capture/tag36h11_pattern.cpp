#include "capture/tag36h11_pattern.h"

#include <memory>
#include <string>

#include <apriltag/apriltag.h>
#include <apriltag/tag36h11.h>

#include "core/error.h"

namespace lumar {
namespace {

struct FamilyDeleter {
    void operator()(apriltag_family_t* family) const { tag36h11_destroy(family); }
};
using FamilyPtr = std::unique_ptr<apriltag_family_t, FamilyDeleter>;

FamilyPtr createFamily()
{
    FamilyPtr family(tag36h11_create());
    if (!family) {
        throw RuntimeError("tag36h11: libapriltag could not create the family");
    }
    return family;
}

// The family tables are immutable once created, so one shared instance serves every caller.
const apriltag_family_t& family()
{
    static const FamilyPtr instance = createFamily();
    return *instance;
}

} // namespace

int tag36h11CodeCount()
{
    return int(family().ncodes);
}

TagPattern tag36h11Pattern(int id)
{
    const apriltag_family_t& fam = family();
    if (id < 0 || id >= int(fam.ncodes)) {
        throw InputError("tag36h11: no code for id " + std::to_string(id) + " (valid ids are 0.." +
                         std::to_string(fam.ncodes - 1) + ")");
    }
    // Guard the layout this pattern assumes; a different libapriltag table would draw a
    // different tag than the detector's, which the fake camera must never do silently.
    if (fam.total_width != kTag36h11TotalCells || fam.width_at_border != kTag36h11BorderCells || fam.reversed_border ||
        fam.nbits > 64) {
        throw RuntimeError("tag36h11: unexpected family layout in libapriltag");
    }

    TagPattern pattern{};
    constexpr int n = kTag36h11TotalCells;
    for (int row = 0; row < n; ++row) {
        for (int col = 0; col < n; ++col) {
            const bool outerRing = row == 0 || col == 0 || row == n - 1 || col == n - 1;
            pattern[size_t(row * n + col)] = outerRing ? 255 : 0;
        }
    }
    // Data bit i sits at (bit_x[i], bit_y[i]) counted from the black border's corner and is
    // the code's (nbits-1-i)-th bit, most significant first: apriltag_to_image's layout.
    const int borderStart = (fam.total_width - fam.width_at_border) / 2;
    const uint64_t code = fam.codes[id];
    for (uint32_t i = 0; i < fam.nbits; ++i) {
        const int col = int(fam.bit_x[i]) + borderStart;
        const int row = int(fam.bit_y[i]) + borderStart;
        if (col <= 0 || row <= 0 || col >= n - 1 || row >= n - 1) {
            throw RuntimeError("tag36h11: bit position outside the tag in libapriltag's table");
        }
        const bool white = (code >> (fam.nbits - 1 - i)) & 1u;
        pattern[size_t(row * n + col)] = white ? 255 : 0;
    }
    return pattern;
}

} // namespace lumar
