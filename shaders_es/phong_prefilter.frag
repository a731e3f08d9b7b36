#version 300 es
// A glossy map: the environment convolved with a normalised Phong lobe cos^n, one cube face
// per draw, as a weighted sum of lookups at fixed directions about the texel's direction.
// glossy-2 (from the mirror map): directions with density proportional to the lobe, equal
// weights, each read from the mip level whose texels cover about its own solid angle
// (filtered importance sampling, IblPipeline::makeLobePrefilter). glossy-1 (cascaded from
// glossy-2): equal-solid-angle samples of the lobe's cap weighted by cos^n, one level.
// SAMPLE_LEVELS (defined or not): read the level of each sample's entry, or level 0 alone.
precision highp float;
precision highp sampler2D;

uniform mat3 uEnvironmentFromFace;
uniform sampler2D uEnvironment; // a cube atlas (cube_atlas.glsl)
// Sample k: uSamples[k] its direction about +z (xyz) and normalised weight (w); uLevels[k]
// the level it reads (x, an integer: LINEAR_MIPMAP_NEAREST reads that level alone) and that
// level's clamp half a texel inside a face (y, cube_atlas.glsl's stMin). A uniform block,
// not a texture: every fragment reads the same entry k, a uniform load instead of a texture
// fetch in the inner loop. 2 x 512 entries: 16 KB, GLES 3.0's least GL_MAX_UNIFORM_BLOCK_SIZE.
layout(std140) uniform LobeSamples {
    vec4 uSamples[512];
    vec4 uLevels[512];
};
uniform int uSampleCount;
uniform vec2 uAtlasSize; // the whole bank's, level 0
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
    // Once, not per sample (but SAMPLE_LEVELS' clamp).
    CubeBankLevel level = cubeBankLevel(uAtlasSize, uSlot, 0.0);
    // decodeMapTexel folded into the weight: a float texel's alpha is 1 (scale 1 exactly).
    float alphaScale = uRgbm ? kRgbmRange : 0.0;
    float alphaBias = uRgbm ? 0.0 : 1.0;
    vec3 sum = vec3(0.0);
    for (int k = 0; k < uSampleCount; ++k) {
        vec4 s = uSamples[k];
        vec3 d = t * s.x + b * s.y + r * s.z;
#ifdef SAMPLE_LEVELS
        level.stMin = uLevels[k].y;
        float lod = uLevels[k].x;
#else
        // One level (the source's only one): a constant lod, llvmpipe's cheaper lookup.
        const float lod = 0.0;
#endif
        vec4 texel = textureLod(uEnvironment, cubeBankLevelUv(d, level), lod);
        sum += texel.rgb * (s.w * (texel.a * alphaScale + alphaBias));
    }
    fragColor = encodeMapTexel(sum, uRgbm);
}
