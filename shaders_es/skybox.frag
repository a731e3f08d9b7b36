#version 300 es
// The real environment (equirectangular, linear radiance) seen through one cube-map face:
// the backdrop of every per-object environment map. Depth stays at the far plane.
precision highp float;
precision highp sampler2D;

uniform mat3 uEnvironmentFromFace;
uniform sampler2D uEquirect; // mipmapped
uniform float uLod;          // the mip level whose texels match the face's
uniform float uIntensity;
uniform bool uRgbm;          // the face is RGBA8 RGBM (no float render targets)

in vec3 vFaceDirection;
out vec4 fragColor;

const float PI = 3.14159265358979;

#include "rgbm.glsl"

void main()
{
    vec3 d = normalize(uEnvironmentFromFace * vFaceDirection);
    vec2 uv = vec2(0.5 + atan(d.z, d.x) / (2.0 * PI), acos(clamp(d.y, -1.0, 1.0)) / PI);
    fragColor = encodeMapTexel(textureLod(uEquirect, uv, uLod).rgb * uIntensity, uRgbm);
}
