// The printed image of an AprilTag of any family lumar detects, cell by cell, taken from
// libapriltag's own family tables (apriltag_to_image), so a printed tag carries exactly the
// code the detector looks for.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "tracking/apriltag_family.h"

namespace lumar {

// One tag as printed: `cells` x `cells` squares, row 0 at the top, column 0 at the left.
struct TagPattern {
    int cells = 0;
    std::vector<uint8_t> black; // row-major, 1 where the cell is black

    [[nodiscard]] bool isBlack(int row, int column) const { return black[size_t(row * cells + column)] != 0; }
};

class TagFamilyPatterns {
public:
    // Throws InputError for a family the library does not provide.
    explicit TagFamilyPatterns(const std::string& family);

    [[nodiscard]] const std::string& name() const { return name_; }
    [[nodiscard]] int idCount() const;
    // The side the detector measures, in cells (the family's width_at_border: for tag36h11
    // the black square's outer edge). A tag's `size` in metres is this side.
    [[nodiscard]] int borderCells() const;
    // The side of the printed square in cells, quiet zone included: the family's image
    // (total_width, whose outer ring is white for the classic families) plus, for the
    // families with a reversed border (data bits on their outer ring), one white ring more.
    [[nodiscard]] int printedCells() const;
    // Throws InputError for an id outside [0, idCount()).
    [[nodiscard]] TagPattern pattern(int id) const;

private:
    std::string name_;
    AprilTagFamilyPtr family_;
};

} // namespace lumar
