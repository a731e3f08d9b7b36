#version 300 es
// One step up the bloom pyramid (gles_renderer/scene/lens_effects.h): this level's image
// weighted by uWeight plus the coarser level's result, bilinearly doubled, by 1 - uWeight.
// Doubling bilinearly spreads each coarse texel over 4 x 4 fine ones with weights summing to
// its area, so the energy stays; uWeight = 1 / (levels below and including this one) gives
// every level the same share of the bloom.
precision highp float;
precision highp sampler2D;

uniform sampler2D uLevel;
uniform sampler2D uCoarser;
uniform float uWeight;

out vec4 fragColor;

// Compile-time choices (LensEffects links a program per image format and effect): on
// llvmpipe a branch on a uniform runs both sides, texture reads and all.
#ifndef LENS_RGBM
#define LENS_RGBM 0
#endif
const bool kRgbm = LENS_RGBM != 0;

#include "rgbm.glsl"
#include "lens.glsl"

void main()
{
    vec3 level = fetchRadiance(uLevel, ivec2(gl_FragCoord.xy), kRgbm);
    vec3 coarser = sampleRadiance(uCoarser, gl_FragCoord.xy * 0.5, kRgbm);
    fragColor = encodeMapTexel(mix(coarser, level, uWeight), kRgbm);
}
