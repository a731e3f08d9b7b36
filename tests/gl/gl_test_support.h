// Helpers shared by the GL tests: renderer creation that skips where no EGL exists, small
// in-code models, and the published formulas the shading tests compare against.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>

#include <GLES3/gl3.h>
#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include "core/camera_model.h"
#include "core/error.h"
#include "core/image.h"
#include "gles_renderer/assets/gltf_model.h"
#include "gles_renderer/gl/gl_object.h"
#include "gles_renderer/scene/scene_renderer.h"

namespace lumar::test {

// A width x height RGBA8 frame with a depth buffer, bound for drawing (its viewport set) and
// cleared to black; for tests that draw a MeshPass into a frame of their own. Needs a context.
struct FrameTarget {
    GlTexture colour = GlTexture::create();
    GlRenderbuffer depth = GlRenderbuffer::create();
    GlFramebuffer framebuffer = GlFramebuffer::create();

    FrameTarget(int width, int height)
    {
        glBindTexture(GL_TEXTURE_2D, colour.name());
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, width, height);
        glBindRenderbuffer(GL_RENDERBUFFER, depth.name());
        glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
        glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.name());
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, colour.name(), 0);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth.name());
        glViewport(0, 0, width, height);
        glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    }

    [[nodiscard]] static bool complete() { return glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE; }
};

// The renderer, or the reason there is none (a machine without EGL/GLES 3: the caller skips).
struct RendererOrReason {
    std::unique_ptr<SceneRenderer> renderer;
    std::string reason;
};

inline RendererOrReason tryCreateRenderer(int width, int height, RenderOptions options = {})
{
    try {
        return {SceneRenderer::create(width, height, options), {}};
    } catch (const RuntimeError& e) {
        return {nullptr, e.what()};
    }
}

#define LUMAR_RENDERER_OR_SKIP(variable, ...)                                                                          \
    auto variable##OrReason = ::lumar::test::tryCreateRenderer(__VA_ARGS__);                                           \
    if (!variable##OrReason.renderer)                                                                                  \
        GTEST_SKIP() << "no GLES 3 renderer: " << variable##OrReason.reason;                                           \
    SceneRenderer& variable = *variable##OrReason.renderer

inline CameraIntrinsics makeIntrinsics(int width, int height, double fx, double fy, double cx, double cy)
{
    CameraIntrinsics k;
    k.width = width;
    k.height = height;
    k.fx = fx;
    k.fy = fy;
    k.cx = cx;
    k.cy = cy;
    return k;
}

// The largest difference between two images' bytes (code values); INT_MAX when their sizes
// differ, so that a bound on it fails.
inline int maxCodeDifference(const Image8& a, const Image8& b)
{
    if (a.data.size() != b.data.size())
        return std::numeric_limits<int>::max();
    int worst = 0;
    for (size_t i = 0; i < a.data.size(); ++i)
        worst = std::max(worst, std::abs(int(a.data[i]) - int(b.data[i])));
    return worst;
}

inline Image8 solidImage(int width, int height, uint8_t r, uint8_t g, uint8_t b)
{
    Image8 image(width, height, 3);
    for (size_t i = 0; i < image.data.size(); i += 3) {
        image.data[i] = r;
        image.data[i + 1] = g;
        image.data[i + 2] = b;
    }
    return image;
}

inline ImageF uniformEnvironment(float radiance)
{
    ImageF image(16, 8, 3);
    std::fill(image.data.begin(), image.data.end(), radiance);
    return image;
}

// A material that only glows: black base colour, so with a black environment the pixels
// show exactly the tone-mapped emission.
inline GltfMaterial emissiveMaterial(const glm::vec3& emission)
{
    GltfMaterial m;
    m.baseColorFactor = glm::vec4(0, 0, 0, 1);
    m.metallicFactor = 0.0f;
    m.emissiveFactor = emission;
    return m;
}

// A one-primitive model: the quad c0 c1 c2 c3, whose front side is the one it is
// counter-clockwise from (normal = (c1 - c0) x (c2 - c0)).
inline GltfModel makeQuad(const std::array<glm::vec3, 4>& c, const GltfMaterial& material)
{
    GltfModel model;
    GltfPrimitive p;
    p.positions = {c[0], c[1], c[2], c[3]};
    const glm::vec3 normal = glm::normalize(glm::cross(c[1] - c[0], c[2] - c[0]));
    p.normals.assign(4, normal);
    p.uvs = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
    p.tangents.assign(4, glm::vec4(glm::normalize(c[3] - c[0]), 1.0f));
    p.indices = {0, 1, 2, 0, 2, 3};
    p.material = 0;
    model.primitives.push_back(p);
    model.materials.push_back(material);
    model.boundsMin = glm::min(glm::min(c[0], c[1]), glm::min(c[2], c[3]));
    model.boundsMax = glm::max(glm::max(c[0], c[1]), glm::max(c[2], c[3]));
    return model;
}

// An axis-aligned rectangle in the plane z = 0 of its model frame, facing -z (towards a
// camera looking along +z when cameraFromModel has no rotation). In the OpenCV frame (y
// down) the corners run top-left, bottom-left, bottom-right, top-right: counter-clockwise
// as the camera sees them.
inline GltfModel cameraFacingRectangle(float x0, float y0, float x1, float y1, const GltfMaterial& material)
{
    return makeQuad({glm::vec3(x0, y0, 0), glm::vec3(x0, y1, 0), glm::vec3(x1, y1, 0), glm::vec3(x1, y0, 0)}, material);
}

inline glm::dmat4 translation(double x, double y, double z)
{
    glm::dmat4 m(1.0);
    m[3] = glm::dvec4(x, y, z, 1.0);
    return m;
}

// Published formulas, written out here independently of the shaders.

// A camera 1 m above the world's origin looking straight down (world z up, as a marker
// frame): image x along world x, image y along world -y.
inline glm::dmat4 cameraLookingDownFromOneMetre()
{
    glm::dmat4 m(1.0);
    m[1][1] = -1.0;
    m[2][2] = -1.0;
    m[3] = glm::dvec4(0.0, 0.0, 1.0, 1.0);
    return m;
}

// The renderer's camera response (shaders_es/camera_response.glsl, DESIGN.md §6.5): linear up
// to the knee, then an exponential shoulder that meets 1 smoothly.
inline double cameraResponse(double x)
{
    constexpr double kKnee = 0.8;
    if (x <= kKnee)
        return std::max(x, 0.0);
    return kKnee + (1.0 - kKnee) * (1.0 - std::exp(-(x - kKnee) / (1.0 - kKnee)));
}

// IEC 61966-2-1 sRGB encoding.
inline double srgbEncode(double linear)
{
    return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

inline double srgbDecode(double encoded)
{
    return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
}

// The 8-bit code value the renderer should write for linear radiance `radiance`.
inline int toneMappedCode(double radiance)
{
    return int(std::lround(255.0 * srgbEncode(cameraResponse(radiance))));
}

} // namespace lumar::test
