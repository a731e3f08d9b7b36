#include "markers/tag_pattern.h"

#include <cstdlib>
#include <memory>

#include <apriltag/apriltag.h>
#include <apriltag/common/image_u8.h>

#include "core/error.h"

namespace lumar {
namespace {

// image_u8_destroy() is not among the symbols Debian's libapriltag exports; it frees the
// pixels and the struct, both from calloc (image_u8_create_stride), which is what this does.
void freeTagImage(image_u8_t* image)
{
    if (image) {
        std::free(image->buf);
        std::free(image);
    }
}

} // namespace

TagFamilyPatterns::TagFamilyPatterns(const std::string& family) : name_(family), family_(createAprilTagFamily(family))
{
}

int TagFamilyPatterns::idCount() const
{
    return int(family_->ncodes);
}

int TagFamilyPatterns::borderCells() const
{
    return family_->width_at_border;
}

int TagFamilyPatterns::printedCells() const
{
    return family_->total_width + (family_->reversed_border ? 2 : 0);
}

TagPattern TagFamilyPatterns::pattern(int id) const
{
    if (id < 0 || id >= idCount())
        throw InputError("id " + std::to_string(id) + " is not in " + name_ + " (ids 0-" +
                         std::to_string(idCount() - 1) + ")");
    const std::unique_ptr<image_u8_t, void (*)(image_u8_t*)> image(apriltag_to_image(family_.get(), id), freeTagImage);
    if (!image)
        throw RuntimeError("libapriltag could not draw " + name_ + " id " + std::to_string(id));
    const int quiet = (printedCells() - family_->total_width) / 2;
    TagPattern tag;
    tag.cells = printedCells();
    tag.black.assign(size_t(tag.cells * tag.cells), 0);
    for (int y = 0; y < image->height; ++y)
        for (int x = 0; x < image->width; ++x)
            tag.black[size_t((y + quiet) * tag.cells + x + quiet)] = image->buf[y * image->stride + x] < 128 ? 1 : 0;
    return tag;
}

} // namespace lumar
