#include "tracking/apriltag_family.h"

#include <array>
#include <cstdint>
#include <string_view>

#include <apriltag/apriltag.h>
#include <apriltag/tag16h5.h>
#include <apriltag/tag25h9.h>
#include <apriltag/tag36h11.h>
#include <apriltag/tagCircle21h7.h>
#include <apriltag/tagCircle49h12.h>
#include <apriltag/tagCustom48h12.h>
#include <apriltag/tagStandard41h12.h>
#include <apriltag/tagStandard52h13.h>

#include "core/error.h"

namespace lumar {
namespace {

struct FamilyEntry {
    std::string_view name;
    apriltag_family_t* (*create)();
    void (*destroy)(apriltag_family_t*);
};

constexpr std::array kFamilies{
    FamilyEntry{"tag36h11", tag36h11_create, tag36h11_destroy},
    FamilyEntry{"tag25h9", tag25h9_create, tag25h9_destroy},
    FamilyEntry{"tag16h5", tag16h5_create, tag16h5_destroy},
    FamilyEntry{"tagCircle21h7", tagCircle21h7_create, tagCircle21h7_destroy},
    FamilyEntry{"tagCircle49h12", tagCircle49h12_create, tagCircle49h12_destroy},
    FamilyEntry{"tagStandard41h12", tagStandard41h12_create, tagStandard41h12_destroy},
    FamilyEntry{"tagStandard52h13", tagStandard52h13_create, tagStandard52h13_destroy},
    FamilyEntry{"tagCustom48h12", tagCustom48h12_create, tagCustom48h12_destroy},
};

// The library builds a hash table of every code with up to N flipped bits: 3 slots of 16
// bytes per entry, ncodes * (1 + nbits + nbits*(nbits-1)) entries for N = 2. For the large
// families that is gigabytes, and the library calls exit() when calloc fails, so the number
// of correctable bits is lowered until the table fits this budget.
constexpr double kDecodeTableBudgetBytes = 64.0 * 1024 * 1024;

} // namespace

AprilTagFamilyPtr createAprilTagFamily(const std::string& name)
{
    for (const FamilyEntry& entry : kFamilies) {
        if (entry.name != name)
            continue;
        AprilTagFamilyPtr family(entry.create(), AprilTagFamilyDeleter{entry.destroy});
        if (!family)
            throw RuntimeError("cannot create tag family '" + name + "'");
        return family;
    }
    throw InputError("unknown tag family '" + name + "'");
}

double decodeTableBytes(const apriltag_family& family, int bits)
{
    const double n = family.nbits;
    double entriesPerCode = 1.0;
    if (bits >= 1)
        entriesPerCode += n;
    if (bits >= 2)
        entriesPerCode += n * (n - 1);
    return double(family.ncodes) * entriesPerCode * 3.0 * 16.0;
}

int correctableBitsFor(const apriltag_family& family)
{
    int bits = 2;
    while (bits > 0 && decodeTableBytes(family, bits) > kDecodeTableBudgetBytes)
        --bits;
    return bits;
}

} // namespace lumar
