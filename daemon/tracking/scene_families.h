// The tag families a detector decodes with, split by what the scene uses (issue 18's memory
// budget). For every family it decodes with N correctable bits, libapriltag builds a hash
// table of every code with up to N flipped bits, and writes all of it while building it, so
// all of it is resident: for tag36h11 with 2 bits that is 587 codes x 1,297 variants x 3
// slots x 16 bytes, 36.5 MB, about a seventh of lumar's memory on the car scene. A scene
// uses a handful of ids. So the family is split in two:
// - the scene's ids (the configured markers and the maps' tags), decoded with the configured
//   bit errors corrected: a table of ~250 KiB for four ids;
// - every other id, decoded only when read without error: 28 KiB. Such a tag is never posed
//   (its size is unknown), but the setup overlay, status.json and the trace still name it, so
//   an integrator who printed the wrong id sees which one the camera found.
// tag36h11's codes are at least 11 bits apart, so a code read with up to 2 wrong bits is never
// another id's exact code: the two halves never decode one quad twice.
#pragma once

#include <cstdint>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "tracking/apriltag_family.h"

struct apriltag_detector;
struct apriltag_detection;

namespace lumar {

class SceneFamilies {
public:
    // `sceneIds` empty: the whole family, decoded with `bitErrors` corrected (as the library
    // does it; `lumar detect`, which poses every tag, and a scene that names no id). Ids past
    // the family's last code are ignored. Throws InputError for an unknown family name.
    SceneFamilies(const std::string& familyName, const std::set<int>& sceneIds, int bitErrors);
    ~SceneFamilies();
    // Detectors keep pointers into this object.
    SceneFamilies(const SceneFamilies&) = delete;
    SceneFamilies& operator=(const SceneFamilies&) = delete;

    // Adds the families to `detector`. The library builds each decode table at the first
    // detector it is added to and frees it with the first detector destroyed; detectors
    // sharing these families must all be destroyed before this object.
    void addTo(apriltag_detector& detector) const;

    // The family's id of a detection made with these families.
    [[nodiscard]] int idOf(const apriltag_detection& detection) const;

    // Bit errors corrected for the scene's ids (the whole family's when not split): the
    // setting, lowered where the table would not fit (correctableBitsFor).
    [[nodiscard]] int sceneBitErrors() const { return sceneBits_; }
    [[nodiscard]] bool split() const { return others_ != nullptr; }
    // The bytes of the decode tables the library builds for these families.
    [[nodiscard]] double decodeTableBytes() const;

private:
    // A subset of the base family's codes; `ids[i]` is the family's id of code i.
    struct Subset;
    // A copy of `base` that decodes only the codes of `ids` (ascending), no decode table yet.
    static std::unique_ptr<Subset> makeSubset(const apriltag_family& base, const std::vector<int>& ids);
    AprilTagFamilyPtr base_;
    std::unique_ptr<Subset> scene_;  // null when not split: the base family decodes alone
    std::unique_ptr<Subset> others_; // null when not split, or when the scene uses every id
    int sceneBits_ = 0;
};

} // namespace lumar
