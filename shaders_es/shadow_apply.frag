#version 300 es
// Multiplies the frame (glBlendFunc(GL_DST_COLOR, GL_ZERO)) by the real surfaces' darkening,
// which ShadowPass::drawReceivers shades at a fraction of the frame's resolution
// (phantom_receiver.frag). Drawn over the receivers themselves (phantom_receiver.vert, the
// phantoms where their depth is equal): each pixel knows its own distance from the camera and
// upsamples depth-aware (a joint bilateral filter): of the four texels around it, bilinear
// weights, but only over the texels of its own surface (distance within a tolerance), so the
// darkening keeps to its surface across a depth edge (a real box's outline against the
// table's shadow) instead of bleeding over it by a few texels. Where no texel is its own
// (a sliver narrower than a texel), the one nearest in distance stands in. A ratio of 1
// leaves its pixels exactly as the camera saw them.
//
// APPLY_WRITES_DEPTH 1: drawn with GL_LESS and depth writes as the phantom's depth pass
// (ShadowPass::applyCanWriteDepth), so it keeps every pixel (a discard would lose its depth)
// and writes a ratio of exactly 1 where the darkening is 1: the blend leaves those pixels
// exactly as they were.
//
// APPLY_ONE_SURFACE 1: the buffer holds one receiver alone, a convex phantom
// (ShadowPass::applyOneSurface): its texels are all the pixel's own surface (continuous, within
// the tolerance below) and the others hold no receiver, so the test of each texel's distance
// (the pixel's own by a log2 and its derivatives, four decodes) is only whether it holds a
// receiver. The same weights, for a fifth of the pass's shader work less.
precision highp float;
precision highp sampler2D;

#ifndef APPLY_WRITES_DEPTH
#define APPLY_WRITES_DEPTH 0
#endif
#ifndef APPLY_ONE_SURFACE
#define APPLY_ONE_SURFACE 0
#endif

uniform sampler2D uRatio;      // r: the ratio; gb: the receiver's distance (receiver_distance.glsl)
uniform float uTexelsPerPixel; // 1 / the frame pixels per texel along x and y

in vec3 vPosition;
in vec3 vNormal;

out vec4 fragColor;

#include "receiver_distance.glsl"

// A texel's surface is the pixel's own within 2 % of the distance (a real edge steps by more:
// a 2 cm box seen from a metre, ~6 %), plus what the surface itself changes over the two
// texels' span the taps reach (slanted tables).
const float kSameSurfaceCodes = 117.0; // log2(1.02) * kDistanceCodesPerOctave

void main()
{
    ivec2 size = textureSize(uRatio, 0);
    vec2 p = gl_FragCoord.xy * uTexelsPerPixel - 0.5;
    vec2 base = floor(p);
    vec2 f = p - base;
    ivec2 low = clamp(ivec2(base), ivec2(0), size - 1);
    ivec2 high = clamp(ivec2(base) + 1, ivec2(0), size - 1);
    vec4 t00 = texelFetch(uRatio, low, 0);
    vec4 t10 = texelFetch(uRatio, ivec2(high.x, low.y), 0);
    vec4 t01 = texelFetch(uRatio, ivec2(low.x, high.y), 0);
    vec4 t11 = texelFetch(uRatio, high, 0);
    vec4 ratios = vec4(t00.r, t10.r, t01.r, t11.r);
    vec4 bilinear = vec4((1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y);
#if APPLY_ONE_SURFACE
    // No receiver: both distance channels 1 (kNoReceiverCode).
    vec4 weights =
        bilinear * vec4(lessThan(vec4(t00.g + t00.b, t10.g + t10.b, t01.g + t01.b, t11.g + t11.b), vec4(2.0)));
    float sum = dot(weights, vec4(1.0));
    // None: a sliver narrower than a texel, where the buffer holds no darkening.
    float ratio = sum > 0.0 ? dot(weights, ratios) / sum : 1.0;
#else
    // Before the discard: derivatives need the whole 2 x 2 quad.
    float own = distanceCode(vPosition);
    float slope = abs(dFdx(own)) + abs(dFdy(own));
#if !APPLY_WRITES_DEPTH
    // Most of a receiver is far from every shadow: a top-level discard lets llvmpipe skip the
    // rest for a whole block of pixels.
    if (min(min(ratios.x, ratios.y), min(ratios.z, ratios.w)) >= 1.0)
        discard;
#endif

    vec4 gaps = abs(vec4(decodeDistance(t00.gb), decodeDistance(t10.gb), decodeDistance(t01.gb),
                         decodeDistance(t11.gb)) - own);
    float tolerance = kSameSurfaceCodes + 2.0 * slope / uTexelsPerPixel;
    vec4 weights = bilinear * vec4(lessThanEqual(gaps, vec4(tolerance)));
    float sum = dot(weights, vec4(1.0));
    float ratio;
    if (sum > 0.0) {
        ratio = dot(weights, ratios) / sum;
    } else {
        // Nearest in distance.
        float nearest = min(min(gaps.x, gaps.y), min(gaps.z, gaps.w));
        vec4 isNearest = vec4(equal(gaps, vec4(nearest)));
        ratio = dot(isNearest, ratios) / dot(isNearest, vec4(1.0));
    }
#endif
#if APPLY_WRITES_DEPTH
    ratio = min(ratio, 1.0); // four ratios of 1 give 1 exactly (a sum over itself)
#else
    if (ratio >= 1.0)
        discard;
#endif
    fragColor = vec4(vec3(ratio), 1.0);
}
