#version 300 es
// SH projection of a cube map (see sh_project.glsl).
precision highp float;
precision highp sampler2D;
precision highp samplerCube;

uniform samplerCube uEnvironment;
uniform float uLod; // the mip level whose texels are about a sample's solid angle

vec3 radianceAt(vec3 d)
{
    return textureLod(uEnvironment, d, uLod).rgb;
}

#include "sh_basis.glsl"
#include "sh_project.glsl"
