#version 300 es
// The environment built from the camera (DESIGN.md §6.5), one frame's step: for each texel of
// the equirectangular accumulation map (direction convention of environment_map.h), the
// camera image where the direction falls inside the frame, linearised from sRGB and divided
// by the exposure, blended into the texel's running average. The weight (attachment 1, a
// fraction of uMaxWeight) grows by one per frame that sees the texel, capped so the map keeps
// adapting; texels outside the frame keep what they had. Ping-pong: uPrevious* are the other
// pair of textures.
precision highp float;
precision highp sampler2D;

uniform sampler2D uPreviousRadiance; // texelFetch: linear RGBA16F, or RGBM RGBA8
uniform sampler2D uPreviousWeight;   // texelFetch: r = weight / uMaxWeight
uniform sampler2D uCamera;           // mipmapped RGBA8, sRGB-encoded, t = 0 the image top
uniform mat3 uCameraFromEnvironment;
uniform mat4 uClipFromCamera;
uniform float uExposure;
uniform float uMaxWeight;
uniform bool uRgbm;

layout(location = 0) out vec4 outRadiance;
layout(location = 1) out vec4 outWeight;

const float PI = 3.14159265358979;
// The outer part of the frame (in texture coordinates) where a sample's weight ramps up from
// zero: the seam between what one frame and the next saw blends instead of stepping.
const float kEdgeRamp = 0.08;

#include "rgbm.glsl"

vec3 srgbToLinear(vec3 c)
{
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), step(vec3(0.04045), c));
}

void main()
{
    ivec2 texel = ivec2(gl_FragCoord.xy);
    vec4 previous = texelFetch(uPreviousRadiance, texel, 0);
    vec4 previousWeight = texelFetch(uPreviousWeight, texel, 0);

    vec2 size = vec2(textureSize(uPreviousRadiance, 0));
    vec2 uv = gl_FragCoord.xy / size;
    float phi = (uv.x - 0.5) * 2.0 * PI;
    float theta = uv.y * PI;
    vec3 d = vec3(sin(theta) * cos(phi), cos(theta), sin(theta) * sin(phi));
    // A direction is a point at infinity: w = 0, the camera's translation drops out.
    vec4 clip = uClipFromCamera * vec4(uCameraFromEnvironment * d, 0.0);
    vec2 st = clip.xy / max(clip.w, 1e-6) * 0.5 + 0.5;
    // Sampled before the branch: implicit derivatives (the mip level that matches the
    // texel's footprint in the image) need every fragment of the quad.
    vec3 seen = srgbToLinear(texture(uCamera, st).rgb) / uExposure;
    vec2 edge = min(st, 1.0 - st);
    float sampleWeight = clip.w > 0.0 ? clamp(min(edge.x, edge.y) / kEdgeRamp, 0.0, 1.0) : 0.0;
    if (sampleWeight <= 0.0) {
        // Copied as stored: decoding and encoding RGBM again could drift by a step a frame.
        outRadiance = previous;
        outWeight = previousWeight;
        return;
    }
    float weight = previousWeight.r * uMaxWeight;
    vec3 radiance = (decodeMapTexel(previous, uRgbm) * weight + seen * sampleWeight) / (weight + sampleWeight);
    outRadiance = encodeMapTexel(radiance, uRgbm);
    outWeight = vec4(min(weight + sampleWeight, uMaxWeight) / uMaxWeight, 0.0, 0.0, 1.0);
}
