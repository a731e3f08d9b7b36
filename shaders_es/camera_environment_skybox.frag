#version 300 es
// The real environment built from the camera, seen through one cube-map face: the backdrop
// of every environment map in place of skybox.frag's. Where the camera has seen the
// direction, its running average (camera_environment_accumulate.frag); where not (or only at
// a frame's edge), the fill: the .hdr map, or without one the mean of the current camera
// image (its last mip level, linearised and divided by the exposure).
precision highp float;
precision highp sampler2D;

uniform mat3 uEnvironmentFromFace;
uniform sampler2D uRadiance; // the accumulation map (linear, or RGBM)
uniform sampler2D uWeight;   // r = weight / uMaxWeight
uniform float uMaxWeight;
uniform bool uFillFromHdr;
uniform sampler2D uEquirect; // the .hdr (intensity applied), mipmapped
uniform float uEquirectLod;
uniform sampler2D uCamera;   // mipmapped, sRGB-encoded
uniform float uCameraLod;    // its last level: the image's mean
uniform float uExposure;
uniform bool uRgbm;          // the accumulation map and the face are RGBM

in vec3 vFaceDirection;
out vec4 fragColor;

const float PI = 3.14159265358979;

#include "rgbm.glsl"

vec3 srgbToLinear(vec3 c)
{
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), step(vec3(0.04045), c));
}

void main()
{
    vec3 d = normalize(uEnvironmentFromFace * vFaceDirection);
    vec2 uv = vec2(0.5 + atan(d.z, d.x) / (2.0 * PI), acos(clamp(d.y, -1.0, 1.0)) / PI);
    vec3 fill = uFillFromHdr ? textureLod(uEquirect, uv, uEquirectLod).rgb
                             : srgbToLinear(textureLod(uCamera, vec2(0.5), uCameraLod).rgb) / uExposure;
    // One frame's full weight makes a texel the camera's; the ramp at a frame's edge blends.
    float seen = clamp(textureLod(uWeight, uv, 0.0).r * uMaxWeight, 0.0, 1.0);
    vec3 captured = decodeMapTexel(textureLod(uRadiance, uv, 0.0), uRgbm);
    fragColor = encodeMapTexel(mix(fill, captured, seen), uRgbm);
}
