// The real environment as the mesh shader uses it: SH9 irradiance for diffuse light and a
// mipmapped equirectangular radiance map for specular reflections, with the rotation from
// the camera frame into the environment's frame.
#pragma once

#include <glm/glm.hpp>

#include "core/image.h"
#include "gles_renderer/gl_object.h"
#include "gles_renderer/uniform_blocks.h"

namespace lumar {

class EnvironmentLighting {
public:
    // Starts as a uniform environment of radiance 1 (a "white furnace"), so a renderer
    // that was never given a map still shows its models.
    EnvironmentLighting();

    // `equirect`: linear radiance, 3 channels (environment_map.h's direction convention);
    // `intensity` scales it. Throws InputError for an empty or malformed image or an
    // intensity that is negative or not finite.
    void set(const ImageF& equirect, float intensity);

    // Rotation from the OpenCV camera frame to the environment's frame (+Y up).
    void setRotation(const glm::dmat3& environmentFromCamera);

    // Writes the environment's part of the per-frame block (rotation, SH, specular LOD range).
    void fillUniforms(FrameUniforms& frame) const;
    [[nodiscard]] GLuint specularMap() const { return specularMap_.name(); }

private:
    GlTexture specularMap_;
    glm::vec4 irradianceSH_[9] = {};
    float maxLod_ = 0.0f;
    glm::mat3 environmentFromCamera_{1.0f};
};

} // namespace lumar
