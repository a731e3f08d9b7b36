#version 300 es
// SH projection of an equirectangular (lat-long) map (see sh_project.glsl): the same sums,
// only the lookup differs. Direction convention of gles_renderer/environment_map.h.
precision highp float;
precision highp sampler2D;

uniform sampler2D uEnvironment; // mipmapped, longitude wraps
uniform float uLod;

const float PI = 3.14159265358979;

vec3 radianceAt(vec3 d)
{
    vec2 uv = vec2(0.5 + atan(d.z, d.x) / (2.0 * PI), acos(clamp(d.y, -1.0, 1.0)) / PI);
    return textureLod(uEnvironment, uv, uLod).rgb;
}

#include "sh_basis.glsl"
#include "sh_project.glsl"
