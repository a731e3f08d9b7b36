#include "gles_renderer/gl/cpu_present.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string_view>

#include <GLES2/gl2ext.h>

#include "gles_renderer/gl/gl_check.h"

namespace lumar {

FittedRect fitFrame(int frameWidth, int frameHeight, int windowWidth, int windowHeight)
{
    const double scale = std::min(double(windowWidth) / frameWidth, double(windowHeight) / frameHeight);
    FittedRect r;
    r.width = int(std::lround(frameWidth * scale));
    r.height = int(std::lround(frameHeight * scale));
    r.x = (windowWidth - r.width) / 2;
    r.y = (windowHeight - r.height) / 2;
    return r;
}

CpuPresenter::CpuPresenter()
{
    const auto* extensions = reinterpret_cast<const char*>(glGetString(GL_EXTENSIONS));
    const std::string_view list = extensions ? extensions : "";
    // Whole-word match: the list is space-separated.
    const std::string_view name = "GL_EXT_read_format_bgra";
    for (size_t pos = list.find(name); pos != std::string_view::npos; pos = list.find(name, pos + 1)) {
        const size_t end = pos + name.size();
        if ((pos == 0 || list[pos - 1] == ' ') && (end == list.size() || list[end] == ' '))
            bgraReadable_ = true;
    }
}

void CpuPresenter::write(GLuint framebuffer, int width, int height, const WindowTarget& window,
                         const WindowTarget::CpuPixels& pixels)
{
    const int windowWidth = window.width(), windowHeight = window.height();
    if (windowWidth <= 0 || windowHeight <= 0)
        return;
    GLuint source = framebuffer;
    if (windowWidth != width || windowHeight != height) {
        // Fitted on the GPU (black bars, linear scaling as the EGL path's blit), then read.
        if (windowWidth != fittedWidth_ || windowHeight != fittedHeight_) {
            fittedColour_ = GlRenderbuffer::create();
            fitted_ = GlFramebuffer::create();
            glBindRenderbuffer(GL_RENDERBUFFER, fittedColour_.name());
            glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, windowWidth, windowHeight);
            glBindFramebuffer(GL_FRAMEBUFFER, fitted_.name());
            glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, fittedColour_.name());
            fittedWidth_ = windowWidth;
            fittedHeight_ = windowHeight;
        }
        const FittedRect r = fitFrame(width, height, windowWidth, windowHeight);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fitted_.name());
        glDisable(GL_SCISSOR_TEST);
        glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
        // Both framebuffers keep the image's top in row 0: no flip.
        glBlitFramebuffer(0, 0, width, height, r.x, r.y, r.x + r.width, r.y + r.height, GL_COLOR_BUFFER_BIT,
                          r.width == width && r.height == height ? GL_NEAREST : GL_LINEAR);
        source = fitted_.name();
    }
    glBindFramebuffer(GL_READ_FRAMEBUFFER, source);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glPixelStorei(GL_PACK_ROW_LENGTH, pixels.stride / 4);
    if (bgraReadable_) {
        glReadPixels(0, 0, windowWidth, windowHeight, GL_BGRA_EXT, GL_UNSIGNED_BYTE, pixels.data);
        // An implementation that lists the extension but refuses the source's format: swap on
        // the CPU from now on.
        bgraReadable_ = glGetError() == GL_NO_ERROR;
    }
    if (!bgraReadable_) {
        // R, G, B, A, then swapped in place.
        glReadPixels(0, 0, windowWidth, windowHeight, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data);
        for (int y = 0; y < windowHeight; ++y) {
            uint8_t* row = pixels.data + size_t(y) * size_t(pixels.stride);
            for (int x = 0; x < windowWidth; ++x)
                std::swap(row[4 * x], row[4 * x + 2]);
        }
    }
    glPixelStorei(GL_PACK_ROW_LENGTH, 0);
    checkGlError("reading the frame into the window's memory");
}

} // namespace lumar
