#include "gles_renderer/overlay/overlay_pass.h"

#include <cmath>
#include <cstddef>

#include "gles_renderer/gl/gl_check.h"
#include "gles_renderer/overlay/bitmap_font.h"

namespace lumar {
namespace {

constexpr float kSolid[4][2] = {{-1, -1}, {-1, -1}, {-1, -1}, {-1, -1}};

// The top-left edge of the pixel nearest `v` (pixel centres at integers, OpenCV's convention):
// glyphs land on whole pixels and stay crisp.
double snapToEdge(double v)
{
    return std::round(v) - 0.5;
}

// What the overlay changes of GL's state, put back after it so the frame's own passes find
// what they left (they are drawn again next frame without knowing the overlay ran).
class SavedState {
public:
    SavedState()
    {
        depthTest_ = glIsEnabled(GL_DEPTH_TEST);
        cullFace_ = glIsEnabled(GL_CULL_FACE);
        blend_ = glIsEnabled(GL_BLEND);
        scissor_ = glIsEnabled(GL_SCISSOR_TEST);
        glGetIntegerv(GL_CURRENT_PROGRAM, &program_);
        glGetIntegerv(GL_ACTIVE_TEXTURE, &activeTexture_);
        glActiveTexture(GL_TEXTURE0);
        glGetIntegerv(GL_TEXTURE_BINDING_2D, &texture_);
        glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &vertexArray_);
        glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &arrayBuffer_);
        glGetIntegerv(GL_VIEWPORT, viewport_);
        glGetIntegerv(GL_BLEND_SRC_RGB, &blendSrcRgb_);
        glGetIntegerv(GL_BLEND_DST_RGB, &blendDstRgb_);
        glGetIntegerv(GL_BLEND_SRC_ALPHA, &blendSrcAlpha_);
        glGetIntegerv(GL_BLEND_DST_ALPHA, &blendDstAlpha_);
    }
    SavedState(const SavedState&) = delete;
    SavedState& operator=(const SavedState&) = delete;
    ~SavedState()
    {
        const auto set = [](GLenum cap, GLboolean on) { on ? glEnable(cap) : glDisable(cap); };
        set(GL_DEPTH_TEST, depthTest_);
        set(GL_CULL_FACE, cullFace_);
        set(GL_BLEND, blend_);
        set(GL_SCISSOR_TEST, scissor_);
        glBlendFuncSeparate(GLenum(blendSrcRgb_), GLenum(blendDstRgb_), GLenum(blendSrcAlpha_), GLenum(blendDstAlpha_));
        glUseProgram(GLuint(program_));
        glBindTexture(GL_TEXTURE_2D, GLuint(texture_));
        glActiveTexture(GLenum(activeTexture_));
        glBindVertexArray(GLuint(vertexArray_));
        glBindBuffer(GL_ARRAY_BUFFER, GLuint(arrayBuffer_));
        glViewport(viewport_[0], viewport_[1], viewport_[2], viewport_[3]);
    }

private:
    GLboolean depthTest_, cullFace_, blend_, scissor_;
    GLint program_ = 0, activeTexture_ = 0, texture_ = 0, vertexArray_ = 0, arrayBuffer_ = 0;
    GLint viewport_[4] = {};
    GLint blendSrcRgb_ = 0, blendDstRgb_ = 0, blendSrcAlpha_ = 0, blendDstAlpha_ = 0;
};

} // namespace

OverlayPass::OverlayPass() : program_(linkProgram(kOverlayProgram))
{
    const SavedState saved;
    viewSize_ = uniformLocation(program_, "viewSize");
    glUseProgram(program_.name());
    glUniform1i(uniformLocation(program_, "font"), 0);

    const BitmapFont& font = overlayFont();
    glBindTexture(GL_TEXTURE_2D, font_.name());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_R8, font.atlasWidth(), font.cellHeight, 0, GL_RED, GL_UNSIGNED_BYTE,
                 font.atlas.data());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);

    glBindVertexArray(vertexArray_.name());
    glBindBuffer(GL_ARRAY_BUFFER, vertices_.name());
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<void*>(offsetof(Vertex, x)));
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<void*>(offsetof(Vertex, u)));
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 4, GL_UNSIGNED_BYTE, GL_TRUE, sizeof(Vertex),
                          reinterpret_cast<void*>(offsetof(Vertex, rgba)));
    checkGlError("creating the overlay pass");
}

void OverlayPass::addQuad(const glm::dvec2 (&corners)[4], const float (&uv)[4][2], const OverlayColor& color)
{
    // Two triangles: 0-1-2 and 0-2-3 (corners in order around the quad).
    constexpr int kOrder[6] = {0, 1, 2, 0, 2, 3};
    for (const int i : kOrder)
        batch_.push_back(
            {float(corners[i].x), float(corners[i].y), uv[i][0], uv[i][1], {color.r, color.g, color.b, color.a}});
}

void OverlayPass::addLine(const OverlayLine& line)
{
    if (!(line.widthPx > 0.0f) || line.color.a == 0)
        return;
    const double half = 0.5 * double(line.widthPx);
    const glm::dvec2 delta = line.to - line.from;
    const double length = glm::length(delta);
    if (!std::isfinite(length))
        return;
    // A point (zero length) is drawn as a square of the line's width.
    const glm::dvec2 along = length > 1e-9 ? delta / length * half : glm::dvec2(half, 0.0);
    const glm::dvec2 across(-along.y, along.x);
    const glm::dvec2 corners[4] = {line.from - along - across, line.to + along - across, line.to + along + across,
                                   line.from - along + across};
    addQuad(corners, kSolid, line.color);
}

void OverlayPass::addText(const OverlayText& text)
{
    if (text.text.empty())
        return;
    const BitmapFont& font = overlayFont();
    const int scale = text.scale < 1 ? 1 : text.scale;
    const double left = snapToEdge(text.topLeft.x), top = snapToEdge(text.topLeft.y);
    const double width = font.textWidth(text.text, scale), height = font.cellHeight * scale;
    if (text.background.a > 0) {
        const double p = text.padding;
        const glm::dvec2 box[4] = {{left - p, top - p},
                                   {left + width + p, top - p},
                                   {left + width + p, top + height + p},
                                   {left - p, top + height + p}};
        addQuad(box, kSolid, text.background);
    }
    const float du = 1.0f / float(font.count);
    double x = left;
    for (const char c : text.text) {
        if (c != ' ') {
            const float u0 = float(font.cellOf(c)) * du, u1 = u0 + du;
            const glm::dvec2 cell[4] = {{x, top},
                                        {x + font.cellWidth * scale, top},
                                        {x + font.cellWidth * scale, top + height},
                                        {x, top + height}};
            const float uv[4][2] = {{u0, 0.0f}, {u1, 0.0f}, {u1, 1.0f}, {u0, 1.0f}};
            addQuad(cell, uv, text.color);
        }
        x += font.cellWidth * scale;
    }
}

void OverlayPass::draw(const OverlayScene& scene, GLuint framebuffer, int width, int height)
{
    batch_.clear();
    for (const OverlayLine& line : scene.lines)
        addLine(line);
    for (const OverlayText& text : scene.texts)
        addText(text);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    if (batch_.empty())
        return;

    const SavedState saved;
    glViewport(0, 0, width, height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glDisable(GL_SCISSOR_TEST);
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
    glUseProgram(program_.name());
    glUniform2f(viewSize_, float(width), float(height));
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, font_.name());
    glBindVertexArray(vertexArray_.name());
    glBindBuffer(GL_ARRAY_BUFFER, vertices_.name());
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(batch_.size() * sizeof(Vertex)), batch_.data(), GL_STREAM_DRAW);
    glDrawArrays(GL_TRIANGLES, 0, GLsizei(batch_.size()));
    checkGlError("drawing the overlay");
}

} // namespace lumar
