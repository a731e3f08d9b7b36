// The rendering stage: draws glTF models over the camera image into an offscreen
// framebuffer on a surfaceless EGL/GLES 3 context, and reads the result back.
#pragma once

#include <memory>
#include <span>

#include <glm/glm.hpp>

#include "core/camera_model.h"
#include "core/image.h"
#include "gles_renderer/environment_map.h"
#include "gles_renderer/gltf_model.h"

namespace lumar {

using ModelId = int;

struct DrawItem {
    ModelId model = -1;
    // Model space to the OpenCV camera frame (x right, y down, z forward), metres.
    glm::dmat4 cameraFromModel{1.0};
};

struct RenderOptions {
    // Multisample anti-aliasing samples per pixel (1 = off). Off by default: on llvmpipe
    // with 2 cores, 4x took the demo truck at 1280x720 from 10.5 to 28 ms per frame.
    int samples = 1;
};

class SceneRenderer {
public:
    // Creates the EGL display/context and framebuffers. Throws RuntimeError with a clear
    // message when no EGL or no GLES 3 context is available.
    static std::unique_ptr<SceneRenderer> create(int width, int height);
    static std::unique_ptr<SceneRenderer> create(int width, int height, const RenderOptions& options);
    virtual ~SceneRenderer() = default;

    virtual ModelId addModel(const GltfModel& model) = 0;
    virtual void removeModels() = 0;
    // `equirect` is linear HDR radiance; `intensity` scales it.
    virtual void setEnvironment(const ImageF& equirect, float intensity) = 0;
    // Rotation from the OpenCV camera frame to the environment map's frame (+Y up), so the
    // real environment stays fixed to the world while the camera moves. Identity until set.
    virtual void setEnvironmentRotation(const glm::dmat3& environmentFromCamera) = 0;

    // Composites the models over `backgroundRgb` (3 channels, the output size).
    virtual void render(const Image8& backgroundRgb, const CameraIntrinsics& intrinsics,
                        std::span<const DrawItem> items) = 0;
    // The last rendered frame, 3 channels, row 0 at the top.
    virtual void readback(Image8& rgb) = 0;

    [[nodiscard]] virtual int width() const = 0;
    [[nodiscard]] virtual int height() const = 0;
};

} // namespace lumar
