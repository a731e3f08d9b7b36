#version 300 es
// LENS_FETCH: the frame's pixel is read where it is drawn (GL_EXT_shader_framebuffer_fetch,
// single-sampled targets), not from a copy of the frame.
#ifndef LENS_FETCH
#define LENS_FETCH 0
#endif
#if LENS_FETCH
#extension GL_EXT_shader_framebuffer_fetch : require
#endif
// Adds the lens effects onto the frame (gles_renderer/scene/lens_effects.h). The effects are
// light scattered in the lens, added to what reached the sensor: the frame's pixel is taken
// back through the camera's response (camera_response.glsl) to linear light, the bloom and
// the glare are added, and the response and the sRGB encoding applied again. Where the effects
// add nothing the pixel is left as it was (discarded), exactly.
precision highp float;
precision highp sampler2D;

#if !LENS_FETCH
uniform sampler2D uFrame;  // the frame so far, sRGB-encoded (a copy: the target is drawn into)
#endif
uniform sampler2D uBloom;  // half the frame's size, or unused
uniform sampler2D uGlare;  // smaller than the frame by 1 / uGlareScale, or unused
uniform float uGlareScale;
uniform vec2 uIntensity;   // x: bloom, y: glare

#if LENS_FETCH
inout vec4 fragColor; // the frame so far, sRGB-encoded
#else
out vec4 fragColor;
#endif

// Compile-time choices (LensEffects links a program per image format and effect): on
// llvmpipe a branch on a uniform runs both sides, texture reads and all.
#ifndef LENS_RGBM
#define LENS_RGBM 0
#endif
const bool kRgbm = LENS_RGBM != 0;
#ifndef LENS_BLOOM
#define LENS_BLOOM 0
#endif
#ifndef LENS_GLARE
#define LENS_GLARE 0
#endif

#include "rgbm.glsl"
#include "lens.glsl"
#include "camera_response.glsl"

// The least light the effects must add to a pixel to touch it.
const float kNothing = 1e-5;

// sRGB without pow (llvmpipe's pow is a long polynomial; six per pixel were most of this
// pass). Every pixel the bloom's faint tail reaches (the added light above kNothing: far
// beyond the visible glow) goes through decodeSrgb, the response's inverse and back, so the
// round trip must keep every 8-bit code. Decoding: sRGB's linear segment exactly, above it a
// quartic fitted (least squares in relative error over codes 11 to 255, within 0.4 %), which
// brings every code back within 0.28 of itself. (Ian Taylor's cubic fit, used before, is poor
// on dark codes: it turned codes 1 to 53 up to 5 codes darker, the 396 darker pixels of
// fig. 6's car away from its lamps.) Encoding by Taylor's fit in square roots (as mesh.frag).
vec3 decodeSrgb(vec3 c)
{
    vec3 high = (((-0.133952044 * c + 0.551586300) * c + 0.550038925) * c + 0.029635555) * c + 0.001013825;
    return mix(c * (1.0 / 12.92), high, step(vec3(0.04045), c));
}

vec3 encodeSrgb(vec3 c)
{
    vec3 s1 = sqrt(c);
    vec3 s2 = sqrt(s1);
    vec3 s3 = sqrt(s2);
    vec3 high = 0.662002687 * s1 + 0.684122060 * s2 - 0.323583601 * s3 - 0.0225411470 * c;
    return mix(c * 12.92, high, step(vec3(0.0031308), c));
}

// cameraResponse's inverse; white (which the shoulder only reaches at infinity) comes back as
// the light that makes 254.5 / 255.
vec3 inverseResponse(vec3 y)
{
    vec3 shoulder = kResponseKnee - (1.0 - kResponseKnee) * log(1.0 - (min(y, 254.5 / 255.0) - kResponseKnee) /
                                                                      (1.0 - kResponseKnee));
    return mix(y, shoulder, step(vec3(kResponseKnee), y));
}

void main()
{
    vec3 added = vec3(0.0);
#if LENS_BLOOM
    added += uIntensity.x * sampleRadiance(uBloom, gl_FragCoord.xy * 0.5, kRgbm);
#endif
#if LENS_GLARE
    added += uIntensity.y * sampleRadiance(uGlare, gl_FragCoord.xy * uGlareScale, kRgbm);
#endif
    if (max(added.r, max(added.g, added.b)) < kNothing)
        discard;
#if LENS_FETCH
    vec3 frame = decodeSrgb(fragColor.rgb);
#else
    vec3 frame = decodeSrgb(texelFetch(uFrame, ivec2(gl_FragCoord.xy), 0).rgb);
#endif
    fragColor = vec4(encodeSrgb(cameraResponse(inverseResponse(frame) + added)), 1.0);
}
