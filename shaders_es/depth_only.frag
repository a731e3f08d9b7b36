#version 300 es
// Writes depth alone: no colour output, so the rasteriser runs no shading for phantoms.
// With ALPHA_CUTOUT (the shadow map's variant for casters that are not opaque) it first cuts
// the surface where mesh.frag does, for glTF alphaMode MASK: base colour alpha (factor x
// texel x vertex colour) below the cutoff, so a leaf casts a leaf-shaped shadow. Then it lets
// light through translucent casters (alphaMode BLEND, transmission: glass) by an ordered
// dither: of each 4 x 4 block of the map's texels it keeps round(16 x opacity), and the
// lookups' PCF kernel (shadow.glsl, about 4 texels wide) averages them into a partial shadow.
// Chosen over a second map carrying the casters' transmittance because the receivers need no
// change (every view that reads the map, the environment maps' faces too, gets it), costs
// nothing where there is no translucent caster, and takes no further texture unit from
// mesh.frag (it uses 16, GLES 3's minimum). What it cannot show: coloured shadows (the
// transmittance is the tint's mean), opacity finer than 1/16, and stacked layers compounding
// (every layer keeps the same texels, so two 50% panes shadow as one).
// Glass that is neither MASK nor BLEND has one opacity over its surface: ShadowPass keeps the
// same texels of it through the map's stencil (shadow_dither_stencil.frag) with the plain
// variant, which discards nothing. ShadowPass links the cut-out variant twice: HAS_BASE_COLOR_TEXTURE 0 for materials without a
// base colour texture (their alpha is the factor x vertex colour: no lookup, no uvs).
precision mediump float;

#ifdef ALPHA_CUTOUT
// The Material block (material_block.glsl), of which this reads the base colour factor, the
// alpha mode and cutoff, the base colour's uv transform and what passes through.
#include "material_block.glsl"

#ifndef HAS_BASE_COLOR_TEXTURE
#define HAS_BASE_COLOR_TEXTURE 1
#endif
#if HAS_BASE_COLOR_TEXTURE
uniform sampler2D uBaseColor;
#endif

in highp vec2 vUv;
in highp vec2 vUv1;
in vec4 vColor;

// A 4 x 4 Bayer matrix: each threshold once, neighbours far apart in order.
const float kBayer[16] = float[16](0.0, 8.0, 2.0, 10.0, 12.0, 4.0, 14.0, 6.0, 3.0, 11.0, 1.0, 9.0, 15.0, 7.0, 13.0, 5.0);

// The share of the light the surface stops: the blended coverage, and of it what the glass
// does not let through (the light it reflects, F0, and what its tint absorbs; the metal share
// of a metallic-roughness material passes none).
float opacity(float alpha)
{
    float coverage = alphaUnlitOcclusion.x > 1.5 ? clamp(alpha, 0.0, 1.0) : 1.0;
    float through = transmission.x * (1.0 - transmission.z) * dot(transmissionTint.rgb, vec3(1.0 / 3.0));
    if (metallicRoughness.z < 0.5)
        through *= 1.0 - metallicRoughness.x;
    return coverage * (1.0 - clamp(through, 0.0, 1.0));
}
#endif

void main()
{
#ifdef ALPHA_CUTOUT
#if HAS_BASE_COLOR_TEXTURE
    highp vec3 uv = vec3(uvTransforms[0].w > 0.5 ? vUv1 : vUv, 1.0);
    highp vec2 transformed = vec2(dot(uvTransforms[0].xyz, uv), dot(uvTransforms[1].xyz, uv));
    float alpha = baseColorFactor.a * texture(uBaseColor, transformed).a * vColor.a;
#else
    float alpha = baseColorFactor.a * vColor.a;
#endif
    if (alphaUnlitOcclusion.x > 0.5 && alphaUnlitOcclusion.x < 1.5 && alpha < alphaUnlitOcclusion.y)
        discard;
    ivec2 cell = ivec2(gl_FragCoord.xy) & 3;
    if (opacity(alpha) * 16.0 < kBayer[cell.y * 4 + cell.x] + 0.5)
        discard;
#endif
}
