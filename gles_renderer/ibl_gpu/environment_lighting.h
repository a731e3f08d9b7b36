// The real environment: a mipmapped equirectangular radiance texture (the skybox of every
// environment map, intensity applied) and the rotation from the camera frame into the
// environment's frame.
#pragma once

#include <glm/glm.hpp>

#include "core/image.h"
#include "gles_renderer/gl/gl_object.h"

namespace lumar {

class EnvironmentLighting {
public:
    // Starts as a uniform environment of radiance 1 (a "white furnace"), so a renderer
    // that was never given a map still shows its models. `faceSize`: the cube faces the
    // equirect is drawn into (texels a side), each sampling it at the level whose texels match
    // theirs (4 x faceSize round the equator); finer levels are not kept (0: every level).
    explicit EnvironmentLighting(int faceSize = 0);

    // `equirect`: linear radiance, 3 channels (environment_map.h's direction convention);
    // `intensity` scales it. Throws InputError for an empty or malformed image or an
    // intensity that is negative or not finite.
    void set(const ImageF& equirect, float intensity);

    // Rotation from the OpenCV camera frame to the environment's frame (+Y up).
    void setRotation(const glm::dmat3& environmentFromCamera);

    [[nodiscard]] const glm::dmat3& environmentFromCamera() const { return environmentFromCamera_; }
    [[nodiscard]] GLuint equirect() const { return equirect_.name(); }
    // The texture's level 0, which may be a level of the image set() was given.
    [[nodiscard]] int equirectWidth() const { return equirectWidth_; }
    // Counts set() calls: maps built from an older environment are stale.
    [[nodiscard]] int generation() const { return generation_; }

private:
    int faceSize_;
    GlTexture equirect_;
    int equirectWidth_ = 0;
    int generation_ = 0;
    glm::dmat3 environmentFromCamera_{1.0};
};

} // namespace lumar
