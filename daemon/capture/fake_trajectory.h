// The fake camera's path: a smooth, periodic orbit above the tags that keeps all of them in
// view, like a hand-held camera circling a table.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "config/config.h"
#include "core/pose.h"

namespace lumar {

class FakeTrajectory {
public:
    static constexpr double kPeriodSeconds = 12.0;

    // Centres the orbit on the tags' centroid and widens it for layouts larger than one
    // default 16 cm tag, so every tag stays in the 70° field of view.
    explicit FakeTrajectory(const std::vector<FakeTagConfig>& tags);

    // camera_from_world at time `seconds` (periodic in kPeriodSeconds). The camera looks at
    // the centroid from 0.5–0.8 m (times the layout scale), 40–65° above the table, its
    // azimuth swinging ±45° around the table's −y side (so tags read upright), its aim
    // wandering ±3 cm and its roll ±4°.
    [[nodiscard]] Pose cameraFromWorld(double seconds) const;

    [[nodiscard]] glm::dvec2 centre() const { return centre_; }
    [[nodiscard]] double scale() const { return scale_; }

private:
    glm::dvec2 centre_{0.0};
    double scale_ = 1.0;
};

} // namespace lumar
