// The printed image of a tag36h11 marker, cell by cell, generated from libapriltag's own
// family tables so the fake camera draws exactly the codes the detector looks for.
#pragma once

#include <array>
#include <cstdint>

namespace lumar {

// 10×10 cells: a white outer ring (row/column 0 and 9), the black border ring (1 and 8) and
// the 6×6 data bits inside. Row 0 is the tag's top edge, column 0 its left edge.
inline constexpr int kTag36h11TotalCells = 10;
inline constexpr int kTag36h11BorderCells = 8; // the black-bordered square, edge to edge

using TagPattern = std::array<uint8_t, kTag36h11TotalCells * kTag36h11TotalCells>; // 0 or 255

// How many ids the family has (587).
int tag36h11CodeCount();

// The pattern of tag `id`, laid out as libapriltag's apriltag_to_image() draws it (and as the
// official tag36h11 PNGs show it). Throws InputError for an id outside [0, count).
TagPattern tag36h11Pattern(int id);

} // namespace lumar
