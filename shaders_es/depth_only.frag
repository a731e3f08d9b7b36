#version 300 es
// Writes depth alone: no colour output, so the rasteriser runs no shading for phantoms.
// With ALPHA_CUTOUT (the shadow map's variant for glTF alphaMode MASK) it first cuts the
// surface where mesh.frag does: base colour alpha (factor x texel x vertex colour) below the
// cutoff, so a leaf casts a leaf-shaped shadow.
precision mediump float;

#ifdef ALPHA_CUTOUT
// mesh.frag's Material block (uniform_blocks.h), of which the cut-out reads the base colour
// factor, the cutoff and the base colour's uv transform.
layout(std140) uniform Material {
    vec4 baseColorFactor;
    vec4 emissiveNormalScale;
    vec4 metallicRoughness;
    vec4 specularFactor;
    vec4 lobeFactor;
    vec4 textureFlags;
    vec4 alphaUnlitOcclusion; // y: alpha cutoff
    vec4 uvTransforms[16];    // slot 0 (base colour): rows 0 and 1; row 0's w: 1 = TEXCOORD_1
};

uniform sampler2D uBaseColor;

in highp vec2 vUv;
in highp vec2 vUv1;
in vec4 vColor;
#endif

void main()
{
#ifdef ALPHA_CUTOUT
    highp vec3 uv = vec3(uvTransforms[0].w > 0.5 ? vUv1 : vUv, 1.0);
    highp vec2 transformed = vec2(dot(uvTransforms[0].xyz, uv), dot(uvTransforms[1].xyz, uv));
    float alpha = baseColorFactor.a * texture(uBaseColor, transformed).a * vColor.a;
    if (alpha < alphaUnlitOcclusion.y)
        discard;
#endif
}
