#version 300 es
// SH projection of a cube map held as a 2D atlas (see sh_project.glsl, cube_atlas.glsl).
precision highp float;
precision highp sampler2D;

// Its base level moved to the mip level whose texels are about a sample's solid angle, read
// without mipmapping (IblPipeline::readMirrorLevel).
uniform sampler2D uEnvironment;
uniform vec2 uAtlasSize; // px at that level (the whole bank)
uniform vec2 uSlot;      // the slot read and the bank's slot count (cube_atlas.glsl)

#include "cube_atlas.glsl"

// Set once per fragment before the sample loop (prepareRadiance, sh_project.glsl).
CubeBankLevel gLevel;

void prepareRadiance()
{
    gLevel = cubeBankLevel(uAtlasSize, uSlot, 0.0);
}
#define SH_PREPARE_RADIANCE

vec3 radianceAt(vec3 d)
{
    return textureLod(uEnvironment, cubeBankLevelUv(d, gLevel), 0.0).rgb;
}

#include "sh_basis.glsl"
#include "sh_project.glsl"
