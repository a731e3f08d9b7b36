#version 300 es
// One step down the bloom pyramid (gles_renderer/scene/lens_effects.h): the mean of the 2 x 2
// source texels under this one; the first step reads the radiance, which holds only the light
// above the threshold (mesh.frag). A texel covers four source texels, so the image's energy
// (sum x area) is kept.
precision highp float;
precision highp sampler2D;

uniform sampler2D uSource;

out vec4 fragColor;

// Compile-time choices (LensEffects links a program per image format and effect): on
// llvmpipe a branch on a uniform runs both sides, texture reads and all.
#ifndef LENS_RGBM
#define LENS_RGBM 0
#endif
const bool kRgbm = LENS_RGBM != 0;
#ifndef LENS_SOURCE_RGBM
#define LENS_SOURCE_RGBM 0
#endif
const bool kSourceRgbm = LENS_SOURCE_RGBM != 0; // the radiance image's format may differ from the pyramid's

#include "rgbm.glsl"
#include "lens.glsl"

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy) * 2;
    vec3 sum = fetchRadiance(uSource, p, kSourceRgbm) + fetchRadiance(uSource, p + ivec2(1, 0), kSourceRgbm) +
               fetchRadiance(uSource, p + ivec2(0, 1), kSourceRgbm) + fetchRadiance(uSource, p + ivec2(1, 1), kSourceRgbm);
    fragColor = encodeMapTexel(0.25 * sum, kRgbm);
}
