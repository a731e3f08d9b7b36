// The dominant light of a real environment (DESIGN.md §6.5): the directional light whose
// spherical-harmonic projection best explains the environment's anisotropy, following Sloan,
// "Stupid Spherical Harmonics (SH) Tricks" (GDC 2008), "extracting the dominant light":
//   direction  the linear band (l = 1) as a vector, its three colour channels weighted by
//              luminance (Rec. 709), normalised;
//   colour     per channel, the least-squares intensity c minimising the difference between
//              the environment's irradiance SH and that of a light c·δ(ω − d), over bands 1
//              and 2. Band 0 is left out on purpose: a constant sky only adds to band 0, so
//              the fit gives the light the environment's directional part and leaves the
//              ambient part to the rest of the sky (Sloan fits bands 0..1 for a light that
//              replaces the SH; here the light is a share of the environment, DESIGN.md §6.5).
//   cap        at most kMaxDominantLightShare of the irradiance (luminance) on a surface
//              facing the light, scaled as a whole: band 1 is also the sky's gradient (a sky
//              brighter than the ground), which the fit attributes to the light too. On
//              venice_sunset_1k.hdr it finds the light 40 degrees up (the sun is 3 degrees up:
//              the bright sky lifts it) taking 74 % of the irradiance facing it and 99 % of the
//              floor's red: shadows removing that much turn black and teal. Capped at one
//              half, the floor keeps about half its light in the umbra.
// The colour is irradiance on a surface facing the light (the environment's radiance units
// times steradians), the E_L = colour·max(0, n·l) that shadows remove.
#pragma once

#include <glm/glm.hpp>

#include "core/image.h"
#include "gles_renderer/assets/environment_map.h"

namespace lumar {

inline constexpr double kMaxDominantLightShare = 0.5;

struct DominantLight {
    glm::vec3 direction{0.0f, 1.0f, 0.0f}; // unit, towards the light, environment frame (+Y up)
    glm::vec3 color{0.0f};                 // irradiance at normal incidence, linear, >= 0
};

// From nine SH coefficients (environment_map.h's basis and order). An environment with no
// linear band (a constant sky) has no dominant light: colour 0, direction +Y.
DominantLight dominantLightFromSH9(const SH9& sh);

// From an equirectangular radiance map (projectEquirectSH9, then the above). Throws
// InputError for an image that is not 3-channel.
DominantLight dominantLight(const ImageF& equirect);

} // namespace lumar
