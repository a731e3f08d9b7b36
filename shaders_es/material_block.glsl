// The per-material std140 block (binding kMaterialBlockBinding), mirrored member for member by
// MaterialUniforms in gles_renderer/scene/uniform_blocks.h (whose static_asserts pin the
// offsets). One declaration for every program that reads it (mesh.frag, phantom.frag,
// depth_only.frag's cut-out variant): a member added here reaches them all, and each reads
// the members it needs.
layout(std140) uniform Material {
    vec4 baseColorFactor;     // metallic-roughness: base colour; Lafortune: rho_d (rgb); a: alpha
    vec4 emissiveNormalScale; // xyz: emissive factor, w: normal-map scale
    vec4 metallicRoughness;   // x: metallic, y: roughness, z: 1 = Lafortune parameters, w: phi
    vec4 specularFactor;      // rgb: rho_s (Lafortune), w: tangent rotation / pi (x texel)
    vec4 lobeFactor;          // xyz: C_x, C_y, C_z, w: exponent n (Lafortune)
    vec4 textureFlags;        // 1 where the texture exists: base, mr/specular, lobe, rotation
    // x: alpha mode (0 opaque, 1 mask, 2 blend), y: alpha cutoff, z: 1 = unlit, w: occlusion
    // strength (0: no occlusion texture).
    vec4 alphaUnlitOcclusion;
    // Per texture slot (base, mr, normal, emissive, occlusion, specular, lobe, rotation): two
    // rows of the uv transform (KHR_texture_transform); row 0's w: 1 = TEXCOORD_1.
    vec4 uvTransforms[16];
    // Light through the surface: x factor, y 1/ior, z dielectric F0, w 1 = transmission texture.
    vec4 transmission;
    vec4 transmissionTint; // rgb: tint x the volume's attenuation
    vec4 transmissionUv[2];
};
