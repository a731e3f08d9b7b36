#version 300 es
// A glossy map: the environment convolved with a normalised Phong lobe cos^n, one cube face
// per draw. The lobe is integrated with equal-solid-angle samples of the cap where cos^n
// matters (the same uniform-sample idea as the SH projection), each weighted by cos^n and
// normalised to sum to one (uSamples.w), read from a mip level whose texels are about one
// sample's solid angle so no radiance falls between samples.
precision highp float;
precision highp sampler2D;

uniform mat3 uEnvironmentFromFace;
uniform sampler2D uEnvironment; // a cube atlas (cube_atlas.glsl)
// xyz around +z, w the normalised weight. A uniform block, not a texture: every fragment
// reads the same entry k, a uniform load instead of a texture fetch in the inner loop.
// 1024 entries: 16 KB, GLES 3.0's smallest GL_MAX_UNIFORM_BLOCK_SIZE.
layout(std140) uniform LobeSamples {
    vec4 uSamples[1024];
};
uniform int uSampleCount;
// Its base level is the mip level to read (IblPipeline moves it there), uAtlasSize px.
uniform vec2 uAtlasSize; // the whole bank's
uniform vec2 uSlot;      // the slot read and the bank's slot count (cube_atlas.glsl)
uniform bool uRgbm; // source and face are RGBA8 RGBM (no float render targets)

in vec3 vFaceDirection;
out vec4 fragColor;

#include "cube_atlas.glsl"
#include "rgbm.glsl"

void main()
{
    vec3 r = normalize(uEnvironmentFromFace * vFaceDirection);
    vec3 helper = abs(r.z) < 0.9 ? vec3(0.0, 0.0, 1.0) : vec3(1.0, 0.0, 0.0);
    vec3 t = normalize(cross(helper, r));
    vec3 b = cross(r, t);
    CubeBankLevel level = cubeBankLevel(uAtlasSize, uSlot, 0.0); // once, not per sample
    // decodeMapTexel folded into the weight: a float texel's alpha is 1 (scale 1 exactly).
    float alphaScale = uRgbm ? kRgbmRange : 0.0;
    float alphaBias = uRgbm ? 0.0 : 1.0;
    vec3 sum = vec3(0.0);
    for (int k = 0; k < uSampleCount; ++k) {
        vec4 s = uSamples[k];
        vec3 d = t * s.x + b * s.y + r * s.z;
        vec4 texel = textureLod(uEnvironment, cubeBankLevelUv(d, level), 0.0);
        sum += texel.rgb * (s.w * (texel.a * alphaScale + alphaBias));
    }
    fragColor = encodeMapTexel(sum, uRgbm);
}
