// Where a configured object sits on its marker. glTF models are Y-up with arbitrary origins;
// the marker frame is Z-up (core/pose.h: x right, y up the tag, z out of the tag). A model is
// stood on the marker, upright and centred, then turned and moved as the config says:
//
//   markerFromModel = T(offset) · Rz(heading) · T(0, 0, lift) · R(rotation) · Rx(+90°) · S · T(−centre)
//
// read right to left:
//   T(−centre)    the centre of the model's bounding box goes to the origin;
//   S             uniform scale (`size` fits the longest side, else `scale`);
//   Rx(+90°)      model +Y (glTF up) becomes marker +Z, model +X stays +X, model +Z (glTF
//                 front) → −Y: the upright frame, the model as authored turned Z-up;
//   R(rotation)   the general case, rarely needed: Rz·Ry·Rx (degrees; x first, then y, then
//                 z) about the marker's axes through the model's centre — in the upright
//                 frame, before heading, so rotation = [-90, 0, 0] stands up a model authored
//                 Z-up whatever its heading;
//   T(0, 0, lift) the turned bounding box is set back on the tag: its lowest point on the
//                 plane z = 0 (for a turned model the box's lowest corner, so a tilted model
//                 may float by the gap between its box and its geometry);
//   Rz(heading)   the common case: degrees about the marker's normal (+Z), counter-clockwise
//                 seen from above, through the model's footprint centre; heading 90 turns
//                 model +X to marker +Y;
//   T(offset)     metres in the marker frame.
//
// Why this order: heading and offset are what a user sets for a model that is already
// upright, and they keep it standing whatever they are; rotation fixes or tilts the model
// itself, so it acts before heading and keeps meaning the same thing when heading changes
// (a yaw/pitch/roll about a turning up axis would make a tilt's direction depend on heading).
// The lift keeps "lowest point on the tag's plane" true for any rotation; before it, a
// rotation about x or y pivoted on the bottom centre and sank half the model into the table.
// Both given: rotation first, then heading; since both z turns are about the vertical,
// heading h with rotation [0, 0, z] is the same as heading h + z.
#pragma once

#include <glm/glm.hpp>

#include "config/config.h"

namespace lumar {

glm::dmat4 markerFromModel(const ObjectConfig& object, const glm::vec3& boundsMin, const glm::vec3& boundsMax);

} // namespace lumar
