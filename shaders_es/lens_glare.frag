#version 300 es
// Glare streaks (gles_renderer/scene/lens_effects.h): each texel gathers the bright image
// from behind it along every streak direction, with weights that fall off exponentially over
// the streak's length. The weights over all directions and samples sum to 1, so the streaks
// carry the bright image's energy, redistributed.
precision highp float;
precision highp sampler2D;

const int kMaxStreaks = 16;
const int kMaxSamples = 32;

uniform sampler2D uSource;       // the bright image, thresholded
uniform vec2 uSteps[kMaxStreaks]; // per streak: one sample's offset along it, source texels
uniform int uStreaks;
uniform int uSamples;
uniform float uWeights[kMaxSamples]; // by sample index, over all streaks summing to 1

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
    vec2 p = gl_FragCoord.xy;
    // The centre sample belongs to every streak: taken once, with their summed weight.
    vec3 sum = float(uStreaks) * uWeights[0] * fetchRadiance(uSource, ivec2(p), kRgbm);
    for (int s = 0; s < uStreaks; ++s)
        for (int i = 1; i < uSamples; ++i) {
            vec2 q = p - uSteps[s] * float(i);
            // RGBM is not filterable: the nearest texel (each sample still moves energy whole).
            vec3 texel = kRgbm ? fetchRadiance(uSource, ivec2(floor(q)), true)
                               : textureLod(uSource, q / vec2(textureSize(uSource, 0)), 0.0).rgb;
            sum += uWeights[i] * texel;
        }
    fragColor = encodeMapTexel(sum, kRgbm);
}
