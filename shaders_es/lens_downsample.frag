#version 300 es
// One step down the bloom pyramid (gles_renderer/scene/lens_effects.h): the mean of the 2 x 2
// source texels under this one, each first reduced by the bright-pass threshold (0 past the
// first level). A texel covers four source texels, so the image's energy (sum x area) is kept.
precision highp float;
precision highp sampler2D;

uniform sampler2D uSource;
uniform float uThreshold;
uniform bool uSourceRgbm; // the radiance image's format may differ from the pyramid's
uniform bool uRgbm;

out vec4 fragColor;

#include "rgbm.glsl"
#include "lens.glsl"

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy) * 2;
    vec3 sum = max(fetchRadiance(uSource, p, uSourceRgbm) - uThreshold, 0.0) +
               max(fetchRadiance(uSource, p + ivec2(1, 0), uSourceRgbm) - uThreshold, 0.0) +
               max(fetchRadiance(uSource, p + ivec2(0, 1), uSourceRgbm) - uThreshold, 0.0) +
               max(fetchRadiance(uSource, p + ivec2(1, 1), uSourceRgbm) - uThreshold, 0.0);
    fragColor = encodeMapTexel(0.25 * sum, uRgbm);
}
