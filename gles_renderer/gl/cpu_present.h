// Presentation through CPU memory (WindowTarget::cpuPixels): the finished frame fitted into the
// window's size (aspect kept, black bars) and read back as B, G, R, X pixels straight into the
// target's memory, which the target then shows (an X11 window through MIT-SHM).
#pragma once

#include "gles_renderer/gl/gl_object.h"
#include "gles_renderer/gl/window_target.h"

namespace lumar {

// Where a `frameWidth` x `frameHeight` frame lands in a `windowWidth` x `windowHeight` window,
// scaled to fit with its aspect kept and centred: [x, x + width) x [y, y + height).
struct FittedRect {
    int x = 0, y = 0, width = 0, height = 0;
};
FittedRect fitFrame(int frameWidth, int frameHeight, int windowWidth, int windowHeight);

class CpuPresenter {
public:
    // Needs a current GLES 3 context.
    CpuPresenter();
    // Writes the frame in `framebuffer` (`width` x `height`, row 0 the image's top) into
    // `pixels`, fitted to `window`'s size. Throws RuntimeError on a GL error.
    void write(GLuint framebuffer, int width, int height, const WindowTarget& window,
               const WindowTarget::CpuPixels& pixels);

private:
    bool bgraReadable_ = false; // GL_EXT_read_format_bgra: B, G, R, A straight from glReadPixels
    int fittedWidth_ = 0, fittedHeight_ = 0;
    GlRenderbuffer fittedColour_; // the window-sized frame, when it is not the frame's size
    GlFramebuffer fitted_;
};

} // namespace lumar
