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
// the tolerance below) and the others hold no receiver, so the weights are the bilinear ones
// over the texels that hold a receiver, and the buffer holds the ratio premultiplied by that
// coverage (alpha): one GL_LINEAR lookup instead of four fetches, a log2, derivatives and four
// decodes. Its 8-bit filtering rounds the ratio once more (car.toml: 1.3 % of the frame's
// pixels change by one code value, none by more); the receivers' CPU time ~2 ms less a frame.
precision highp float;
precision highp sampler2D;

#ifndef APPLY_WRITES_DEPTH
#define APPLY_WRITES_DEPTH 0
#endif
#ifndef APPLY_ONE_SURFACE
#define APPLY_ONE_SURFACE 0
#endif

// r: the ratio x a; gb: the receiver's distance (receiver_distance.glsl); a: 1 where a receiver
// is, else 0 (r 0 there too). GL_LINEAR: texelFetch ignores it.
uniform sampler2D uRatio;
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
#if APPLY_ONE_SURFACE
    // Red holds ratio x coverage and alpha the coverage: one bilinear lookup (GL_LINEAR) sums
    // both with the same weights; none covered (a sliver narrower than a texel) holds no
    // darkening.
    vec4 filtered = textureLod(uRatio, gl_FragCoord.xy * uTexelsPerPixel / vec2(size), 0.0);
    float ratio = filtered.a > 0.0 ? filtered.r / filtered.a : 1.0;
#else
    vec2 p = gl_FragCoord.xy * uTexelsPerPixel - 0.5;
    vec2 base = floor(p);
    vec2 f = p - base;
    ivec2 low = clamp(ivec2(base), ivec2(0), size - 1);
    ivec2 high = clamp(ivec2(base) + 1, ivec2(0), size - 1);
    vec4 t00 = texelFetch(uRatio, low, 0);
    vec4 t10 = texelFetch(uRatio, ivec2(high.x, low.y), 0);
    vec4 t01 = texelFetch(uRatio, ivec2(low.x, high.y), 0);
    vec4 t11 = texelFetch(uRatio, high, 0);
    // A texel without a receiver holds red 0 and alpha 0: its ratio is 1.
    vec4 ratios = vec4(t00.r, t10.r, t01.r, t11.r) + (1.0 - vec4(t00.a, t10.a, t01.a, t11.a)); // exact
    vec4 bilinear = vec4((1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y);
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
