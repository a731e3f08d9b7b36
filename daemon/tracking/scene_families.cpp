#include "tracking/scene_families.h"

#include <algorithm>

#include <apriltag/apriltag.h>

namespace lumar {

struct SceneFamilies::Subset {
    apriltag_family_t family{}; // the base family's geometry and bit layout, these codes
    std::vector<uint64_t> codes;
    std::vector<int> ids;
    int bits = 0;
};

std::unique_ptr<SceneFamilies::Subset> SceneFamilies::makeSubset(const apriltag_family_t& base,
                                                                 const std::vector<int>& ids)
{
    auto subset = std::make_unique<SceneFamilies::Subset>();
    subset->ids = ids;
    subset->codes.reserve(ids.size());
    for (const int id : ids)
        subset->codes.push_back(base.codes[id]);
    subset->family = base; // bit_x, bit_y and name stay the base family's: it outlives the copy
    subset->family.ncodes = uint32_t(subset->codes.size());
    subset->family.codes = subset->codes.data();
    subset->family.impl = nullptr;
    return subset;
}

SceneFamilies::SceneFamilies(const std::string& familyName, const std::set<int>& sceneIds, int bitErrors)
    : base_(createAprilTagFamily(familyName))
{
    const int ncodes = int(base_->ncodes);
    std::vector<int> scene, others;
    for (int id = 0; id < ncodes; ++id)
        (sceneIds.contains(id) ? scene : others).push_back(id);
    if (scene.empty() || others.empty()) {
        sceneBits_ = std::min(bitErrors, correctableBitsFor(*base_));
        return;
    }
    scene_ = makeSubset(*base_, scene);
    others_ = makeSubset(*base_, others);
    sceneBits_ = std::min(bitErrors, correctableBitsFor(scene_->family));
    scene_->bits = sceneBits_;
    others_->bits = 0;
}

SceneFamilies::~SceneFamilies() = default;

void SceneFamilies::addTo(apriltag_detector& detector) const
{
    if (!scene_) {
        apriltag_detector_add_family_bits(&detector, base_.get(), sceneBits_);
        return;
    }
    apriltag_detector_add_family_bits(&detector, &scene_->family, scene_->bits);
    apriltag_detector_add_family_bits(&detector, &others_->family, others_->bits);
}

int SceneFamilies::idOf(const apriltag_detection& detection) const
{
    const int index = detection.id;
    if (scene_ && detection.family == &scene_->family)
        return scene_->ids[size_t(index)];
    if (others_ && detection.family == &others_->family)
        return others_->ids[size_t(index)];
    return index; // the base family: its own ids
}

double SceneFamilies::decodeTableBytes() const
{
    if (!scene_)
        return lumar::decodeTableBytes(*base_, sceneBits_);
    return lumar::decodeTableBytes(scene_->family, scene_->bits) +
           lumar::decodeTableBytes(others_->family, others_->bits);
}

} // namespace lumar
