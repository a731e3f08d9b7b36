// Draws an OverlayScene (lines and text) over a finished frame in its framebuffer, alpha
// blended, after compositing: what reads the frame back or presents it then shows it. One
// vertex buffer a frame, one draw call; the font is a texture uploaded once.
#pragma once

#include <vector>

#include "gles_renderer/gl/gl_object.h"
#include "gles_renderer/gl/shader_program.h"
#include "gles_renderer/overlay/overlay_scene.h"

namespace lumar {

inline constexpr ProgramSources kOverlayProgram{"overlay.vert", "overlay.frag"};

class OverlayPass {
public:
    // Needs a current GLES 3 context. Throws RuntimeError.
    OverlayPass();

    // Draws `scene` into `framebuffer` (`width` x `height`, its row 0 the image's top row);
    // leaves that framebuffer bound and the rest of GL's state as it found it.
    void draw(const OverlayScene& scene, GLuint framebuffer, int width, int height);

private:
    struct Vertex {
        float x, y;      // pixels, OpenCV convention
        float u, v;      // font atlas coordinates; u < 0: solid colour
        uint8_t rgba[4]; // normalised
    };
    void addQuad(const glm::dvec2 (&corners)[4], const float (&uv)[4][2], const OverlayColor& color);
    void addLine(const OverlayLine& line);
    void addText(const OverlayText& text);

    GlProgram program_;
    GLint viewSize_ = -1;
    GlTexture font_ = GlTexture::create();
    GlVertexArray vertexArray_ = GlVertexArray::create();
    GlBuffer vertices_ = GlBuffer::create();
    std::vector<Vertex> batch_; // reused from frame to frame
};

} // namespace lumar
