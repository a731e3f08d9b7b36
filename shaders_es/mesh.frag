#version 300 es
// The paper's shading (Pessoa et al. 2009; DESIGN.md §6.4): McAllister's Lafortune SBRDF
// with a per-texel tangent rotation and the paper's Fresnel factor, lit by the object's own
// four environment maps (diffuse, two glossy, mirror) blended by glossiness, plus emission.
// The main view applies the camera's response (camera_response.glsl) and sRGB-encodes for the RGBA8 target; a cube-face view of
// an environment map writes linear HDR radiance.
precision highp float;
precision highp sampler2D;
precision highp sampler2DShadow;

layout(std140) uniform Frame {
    mat4 clipFromCamera;
    mat3 environmentFromCamera;
    // x: +1, or -1 for a mirrored (cube-face) camera frame, where cross products flip;
    // y: 1 writes linear radiance (environment maps), 0 tone-mapped sRGB (the frame);
    // z: 1 = the maps are RGBA8 RGBM (no float render targets), so decode them, and encode
    // the output too when y is 1; w: exposure, the factor on radiance before tone mapping.
    vec4 frameParams;
    // The dominant light in this view (DESIGN.md §6.5; gles_renderer/scene/uniform_blocks.h).
    mat4 lightClipFromCamera;
    vec4 lightDirection;  // xyz: towards the light; w: 1 = sample the shadow map
    vec4 lightIrradiance; // rgb: irradiance at normal incidence; w: 1 = a light is set
    vec4 shadowParams;    // x: PCF radius (texels), y: 1 / map size, z: normal offset (metres), w: depth bias
    vec4 lensParams;      // x: the lens effects' bright threshold (fragRadiance)
};

#include "material_block.glsl"

uniform sampler2D uBaseColor;         // sRGB: base colour / rho_d
uniform sampler2D uMetallicRoughness; // g: roughness, b: metallic
uniform sampler2D uNormal;            // tangent space
uniform sampler2D uEmissive;          // sRGB
uniform sampler2D uSpecular;          // sRGB: rho_s (Lafortune)
uniform sampler2D uLobe;              // linear: C_x, C_y, C_z, n multipliers (Lafortune)
uniform sampler2D uTangentRotation;   // linear r: x the rotation factor
uniform sampler2D uDiffuseMap;        // E / pi (the n = 1 Phong prefilter), environment frame
uniform sampler2D uGlossy1Map;        // Phong prefilter, n = 8
uniform sampler2D uGlossy2Map;        // Phong prefilter, n = 64
uniform sampler2D uMirrorMap;         // the environment map itself
uniform vec2 uMapSlot;                // the four maps' slot in their bank, the bank's slots (cube_atlas.glsl)
uniform sampler2DShadow uShadowMap;   // the dominant light's depth, compared (shadow.glsl)
uniform sampler2D uOcclusion;         // linear r: ambient occlusion
uniform sampler2D uTransmission;      // linear r: x the transmission factor

// What the material and the view need, fixed when MeshPass links a variant of this program
// for them (gles_renderer/scene/mesh_features.h). llvmpipe runs both sides of every branch,
// uniform ones included, so a lookup a material does not need costs as much as one it does
// unless the compiler removes it (and a discard anywhere in a program turns off its early
// depth test). Where a variant leaves a feature open (the generic program), the uniforms decide.
#ifndef HAS_BASE_COLOR_TEXTURE
#define HAS_BASE_COLOR_TEXTURE (textureFlags.x > 0.5)
#endif
#ifndef HAS_SECOND_TEXTURE // rho_s (Lafortune) or metallic-roughness
#define HAS_SECOND_TEXTURE (textureFlags.y > 0.5)
#endif
#ifndef HAS_LOBE_TEXTURE
#define HAS_LOBE_TEXTURE (textureFlags.z > 0.5)
#endif
#ifndef HAS_ROTATION_TEXTURE
#define HAS_ROTATION_TEXTURE (textureFlags.w > 0.5)
#endif
#ifndef IS_LAFORTUNE
#define IS_LAFORTUNE (metallicRoughness.z > 0.5)
#endif
#ifndef HAS_NORMAL_MAP
#define HAS_NORMAL_MAP (emissiveNormalScale.w != 0.0)
#endif
#ifndef HAS_EMISSION
#define HAS_EMISSION any(greaterThan(emissiveNormalScale.rgb, vec3(0.0)))
#endif
#ifndef HAS_OCCLUSION_TEXTURE
#define HAS_OCCLUSION_TEXTURE (alphaUnlitOcclusion.w > 0.0)
#endif
#ifndef IS_UNLIT
#define IS_UNLIT (alphaUnlitOcclusion.z > 0.5)
#endif
#ifndef ALPHA_MODE // 0 opaque, 1 mask, 2 blend
#define ALPHA_MODE alphaUnlitOcclusion.x
#endif
#ifndef HAS_TRANSMISSION // KHR_materials_transmission or the glass preset
#define HAS_TRANSMISSION (transmission.x > 0.0)
#endif
#ifndef HAS_DIFFUSE // rho_d not zero: the diffuse term (and the shadow, which darkens only it)
#define HAS_DIFFUSE any(notEqual(baseColorFactor.rgb, vec3(0.0)))
#endif
#ifndef HAS_TANGENT_ROTATION // the Lafortune tangent turned by a factor that is not 0
#define HAS_TANGENT_ROTATION (IS_LAFORTUNE && specularFactor.w != 0.0)
#endif
#ifndef PHONG_LOBE // the lobe is Phong's (C = -1, -1, 1 everywhere): its peak is the mirror direction
#define PHONG_LOBE (!IS_LAFORTUNE || (!HAS_LOBE_TEXTURE && lobeFactor.xyz == vec3(-1.0, -1.0, 1.0)))
#endif
#ifndef HAS_VERTEX_EXTRAS // the primitive has COLOR_0 or TEXCOORD_1 (else white and (0, 0))
#define HAS_VERTEX_EXTRAS true
#endif
#ifndef HAS_SHADOW
#define HAS_SHADOW (lightDirection.w > 0.5)
#endif
#ifndef MAPS_RGBM
#define MAPS_RGBM (frameParams.z > 0.5)
#endif
#ifndef WRITES_RADIANCE // a cube face of an environment map, not the frame (never fixed: mesh_features.h)
#define WRITES_RADIANCE (frameParams.y > 0.5)
#endif
#ifndef GLOSS_FLOOR // the least glossiness of the lobe (mesh_features.h glossFeatures)
#define GLOSS_FLOOR 0.0
#endif

in vec3 vPosition;
in vec3 vNormal;
in vec4 vTangent;
in vec2 vUv;
in vec4 vColor; // COLOR_0, linear (white without)
in vec2 vUv1;
// What vColor and vUv1 hold: the constants mesh_pass.cpp sets for primitives without the
// attributes, which need then not be interpolated (llvmpipe interpolates every input a
// shader reads at every pixel: six components of twenty-four).
vec4 vertexColour()
{
    return HAS_VERTEX_EXTRAS ? vColor : vec4(1.0);
}
vec2 secondUv()
{
    return HAS_VERTEX_EXTRAS ? vUv1 : vec2(0.0);
}
// The shadow map coordinates of the position and the normal offset's share per unit of
// vNormal (mesh.vert; shadow.glsl's shadowCoordinatesInterpolated).
in vec3 vShadowCentre;
in vec3 vShadowNormal;

layout(location = 0) out vec4 fragColor;
// The frame's second attachment, where lens effects are on (gles_renderer/scene/lens_effects.h):
// the bright part of the virtual radiance times the exposure, what lies above the threshold
// (lensParams.x), linear HDR (RGBM where the maps are). Thresholded here, texel by texel,
// it is mostly 0 and a software rasteriser's lens effects read it back as it is. Without that
// attachment (lens effects off, cube faces) the write goes nowhere.
layout(location = 1) out vec4 fragRadiance;

#include "lafortune.glsl"
#include "cube_atlas.glsl"
#include "rgbm.glsl"
#include "camera_response.glsl"
#include "shadow.glsl"
#include "normal_map_transform.glsl"

// The least share of the environment's diffuse light a shadow leaves (a configured light may
// claim more of the light than the environment map holds).
const float kShadowFloor = 0.1;
const float kInversePi = 0.31830989;

// sRGB encoding of c in [0, 1]. The power 1/2.4 is replaced by Ian Taylor's fit in square
// roots ("sRGB approximations for HLSL", 2012): within 0.25 code values of the exact curve
// at 8 bits, and about 10% of llvmpipe's time for a model filling the frame cheaper.
vec3 encodeSrgb(vec3 c)
{
    vec3 low = c * 12.92;
    vec3 s1 = sqrt(c);
    vec3 s2 = sqrt(s1);
    vec3 s3 = sqrt(s2);
    vec3 high = 0.662002687 * s1 + 0.684122060 * s2 - 0.323583601 * s3 - 0.0225411470 * c;
    return mix(low, high, step(vec3(0.0031308), c));
}

// Radiance of the environment around direction d (environment frame) for glossiness s.
// Explicit LODs: the maps are small, and implicit derivatives would jump at the borders of
// the atlas cells (cube_atlas.glsl).
vec3 mapRadiance(sampler2D map, CubeFaceHit hit)
{
    vec2 slot = vec2(uMapSlot.x, max(uMapSlot.y, 1.0)); // unset: a single set
    return decodeMapTexel(textureLod(map, cubeHitUv(hit, cubeBankLevel(cubeAtlasSize(map), slot, 0.0)), 0.0),
                          MAPS_RGBM);
}

// The environment's radiance as glossyWeights(s) on the four maps.
vec3 environmentRadiance(vec3 d, float s)
{
    vec4 w = glossyWeights(s);
    CubeFaceHit hit = cubeFaceHit(d); // one face selection for the four lookups
    // The maps below the material's least glossiness weigh 0: left out (in the same order
    // of additions, so the sum is the same).
    vec3 sum = vec3(0.0);
    if (GLOSS_FLOOR < 0.25)
        sum += w.x * mapRadiance(uDiffuseMap, hit);
    if (GLOSS_FLOOR < 0.5)
        sum += w.y * mapRadiance(uGlossy1Map, hit);
    if (GLOSS_FLOOR < 1.0)
        sum += w.z * mapRadiance(uGlossy2Map, hit);
    return sum + w.w * mapRadiance(uMirrorMap, hit);
}

// The uv texture slot `slot` reads: its uv set, transformed (identity without the extension).
vec2 slotUv(int slot)
{
    vec4 row0 = uvTransforms[2 * slot];
    vec3 uv = vec3(row0.w > 0.5 ? secondUv() : vUv, 1.0);
    return vec2(dot(row0.xyz, uv), dot(uvTransforms[2 * slot + 1].xyz, uv));
}

// Light through a transmissive surface (KHR_materials_transmission, _ior, _volume; the glass
// preset; DESIGN.md §6.5), looked up in the object's own environment maps, which show what
// surrounds it (the camera image on phantoms and the sky, the phantoms, the other objects)
// as seen from its centre. The model is a single interface: the view ray -v is bent once at
// the surface by 1/ior (refract) and the maps are read along the bent ray, as if the object
// were glass all the way behind its front surface. Thin-walled materials (no volume,
// thickness 0) do not bend it: the ray goes straight through. What this cannot show: the
// bend where the light leaves (a real ball lens turns the image upside down twice over and
// focuses; here it is bent once), total internal reflection and caustics, the object's own
// other parts (its maps are drawn without it: a car's seats behind its windscreen), the
// parallax of things close to the glass (the maps are seen from the object's centre), and
// attenuation that varies with the path length (the volume's thickness is one number).
// `gloss`: the lobe's glossiness before Fresnel (rough glass reads the blurred maps).
vec3 transmittedRadiance(vec3 v, vec3 n, float gloss)
{
    vec3 bent = refract(-v, n, transmission.y);
    return environmentRadiance(environmentFromCamera * bent, gloss);
}

vec2 transmissionTexelUv()
{
    vec4 row0 = transmissionUv[0];
    vec3 uv = vec3(row0.w > 0.5 ? secondUv() : vUv, 1.0);
    return vec2(dot(row0.xyz, uv), dot(transmissionUv[1].xyz, uv));
}

void main()
{
    // Base colour and alpha first: a MASK cut-out ends here, before any other lookup.
    vec4 baseTexel = vec4(1.0);
    if (HAS_BASE_COLOR_TEXTURE)
        baseTexel = texture(uBaseColor, slotUv(0));
    vec4 colour = vertexColour();
    vec3 base = baseTexel.rgb * colour.rgb;
    float alpha = baseColorFactor.a * baseTexel.a * colour.a;
    // RGBM environment maps keep their scale in alpha: BLEND is drawn as a cut-out there.
    bool blendable = !(WRITES_RADIANCE && MAPS_RGBM);
    float alphaMode = ALPHA_MODE;
    if (alphaMode > 0.5) {
        float cutoff = alphaMode < 1.5 ? alphaUnlitOcclusion.y : (blendable ? -1.0 : 0.5);
        if (alpha < cutoff)
            discard;
    }
    if (alphaMode < 1.5 || !blendable)
        alpha = 1.0;
    // KHR_materials_unlit: the colour is what the frame shows (sRGB-encoded as it is, no
    // exposure or camera response), and the radiance environment maps see.
    if (IS_UNLIT) {
        vec3 colour = clamp(baseColorFactor.rgb * base, 0.0, 1.0);
        vec4 mapTexel = encodeMapTexel(colour, MAPS_RGBM);
        fragColor = WRITES_RADIANCE ? vec4(mapTexel.rgb, blendable ? alpha : mapTexel.a)
                                        : vec4(encodeSrgb(colour), alpha);
        fragRadiance = encodeMapTexel(max(colour * frameParams.w - lensParams.x, 0.0), MAPS_RGBM);
        if (!MAPS_RGBM)
            fragRadiance.a = alpha;
        return;
    }

    // The local frame, normal-mapped, then the tangent turned by the rotation map.
    vec3 n = normalize(vNormal);
    vec3 t = vTangent.xyz - n * dot(n, vTangent.xyz);
    bool hasTangent = dot(t, t) > 1e-12; // meshes without usable uvs have none
    t = hasTangent ? normalize(t) : normalize(abs(n.x) < 0.9 ? cross(n, vec3(1, 0, 0)) : cross(n, vec3(0, 1, 0)));
    float handedness = (vTangent.w < 0.0 ? -1.0 : 1.0) * frameParams.x;
    vec3 b = cross(n, t) * handedness;
    if (HAS_NORMAL_MAP && hasTangent) {
        vec3 tangentNormal = texture(uNormal, slotUv(2)).xyz * 2.0 - 1.0;
        tangentNormal.xy =
            emissiveNormalScale.w * normalMapXyInTangentFrame(tangentNormal.xy, uvTransforms[4], uvTransforms[5]);
        n = normalize(mat3(t, b, n) * tangentNormal);
        t = normalize(t - n * dot(n, t));
    }
    // Back faces of double-sided materials are lit as seen from their side.
    if (!gl_FrontFacing) {
        n = -n;
        t = -t;
    }

    // Absent textures are white: skip their lookups (uniform branches cost nothing).
    vec3 rhoD;
    vec3 rhoS;
    vec3 lobe;
    float exponent;
    float rotation;
    float dielectric = 1.0; // the share of the surface that is not metal (transmission's)
    if (IS_LAFORTUNE) {
        rhoD = baseColorFactor.rgb * base;
        rhoS = specularFactor.rgb;
        if (HAS_SECOND_TEXTURE)
            rhoS *= texture(uSpecular, slotUv(5)).rgb;
        vec4 lobeTexel = vec4(1.0);
        if (HAS_LOBE_TEXTURE)
            lobeTexel = texture(uLobe, slotUv(6));
        lobe = lobeFactor.xyz * lobeTexel.rgb;
        exponent = max(lobeFactor.w * lobeTexel.a, 1.0);
        rotation = specularFactor.w;
        if (HAS_ROTATION_TEXTURE)
            rotation *= texture(uTangentRotation, slotUv(7)).r;
    } else {
        vec3 mr = vec3(1.0);
        if (HAS_SECOND_TEXTURE)
            mr = texture(uMetallicRoughness, slotUv(1)).rgb;
        float metallic = clamp(metallicRoughness.x * mr.b, 0.0, 1.0);
        float roughness = clamp(metallicRoughness.y * mr.g, 0.0, 1.0);
        vec3 colour = baseColorFactor.rgb * base;
        rhoD = colour * (1.0 - metallic);
        rhoS = mix(vec3(HAS_TRANSMISSION ? transmission.z : kDielectricSpecular), colour, metallic);
        dielectric = 1.0 - metallic;
        lobe = vec3(-1.0, -1.0, 1.0);
        exponent = phongExponentFromRoughness(roughness);
        rotation = 0.0;
    }
    // Towards B (mirrored uvs and mirrored cube-face frames turn the other way round). A
    // rotation of 0 leaves t as it is: its sine and cosine are left out.
    if (HAS_TANGENT_ROTATION)
        t = rotateTangent(t, n, rotation * handedness);
    b = cross(n, t) * handedness;

    vec3 v = normalize(-vPosition);
    // A Phong lobe needs no tangent frame (phongShade): without a normal map t and b, and the
    // tangent's interpolation, are left out.
    LafortuneShade shade = PHONG_LOBE ? phongShade(v, n, exponent, rhoS, metallicRoughness.w)
                                      : lafortuneShade(v, t, b, n, lobe, exponent, rhoS, metallicRoughness.w);
    // glTF occlusion darkens the environment's light, diffuse and specular alike (not the
    // emission): 1 + strength (texel - 1).
    float occlusion = 1.0;
    if (HAS_OCCLUSION_TEXTURE)
        occlusion = 1.0 + alphaUnlitOcclusion.w * (texture(uOcclusion, slotUv(4)).r - 1.0);
    // Without a diffuse reflectance (metals, glass: rho_d = 0) the diffuse term is 0 whatever
    // the irradiance, and the shadow darkens nothing else: both are left out (exactly the
    // same image, a map lookup and the shadow's taps fewer).
    vec3 diffuse = vec3(0.0);
    if (HAS_DIFFUSE) {
        vec3 irradiance = mapRadiance(uDiffuseMap, cubeFaceHit(environmentFromCamera * n)); // E_env / pi
        // Shadows (DESIGN.md §6.5): the dominant light is a share of the environment, E_L =
        // lightIrradiance max(0, n.l); where the shadow map blocks it, that share is taken out:
        // E = max(E_env - (1 - visibility) E_L, floor). Lit, or with no light or no shadow map,
        // E is E_env exactly, as without shadows.
        if (HAS_SHADOW) {
            float nl = dot(n, lightDirection.xyz);
            if (nl > 0.0) {
                // Without a normal map n is vNormal normalised (turned round on back faces):
                // the offset along it is the interpolated one, scaled as normalize() does.
                float visibility;
                if (HAS_NORMAL_MAP) {
                    visibility = shadowVisibilityFourTaps(vPosition, n);
                } else {
                    float along = (gl_FrontFacing ? 1.0 : -1.0) * inversesqrt(dot(vNormal, vNormal));
                    visibility =
                        shadowVisibilityFourTapsAt(shadowCoordinatesInterpolated(vShadowCentre, vShadowNormal * along));
                }
                if (visibility < 1.0)
                    irradiance = max(irradiance - (1.0 - visibility) * kInversePi * nl * lightIrradiance.rgb,
                                     kShadowFloor * irradiance);
            }
        }
        diffuse = occlusion * rhoD * irradiance;
    }
    vec3 specular = occlusion * shade.specularWeight *
                    environmentRadiance(environmentFromCamera * shade.lobeDirection, shade.glossiness);
    vec3 radiance = diffuse + specular;
    if (HAS_TRANSMISSION) {
        // glTF: the dielectric's diffuse turns into transmission by `share`; what passes is
        // what the Fresnel-weighted reflection (rho_s' = rho_s + (1 - rho_s) f, the paper's
        // factor, as in specularWeight) leaves, tinted.
        float share = transmission.x * dielectric;
        if (transmission.w > 0.5)
            share *= texture(uTransmission, transmissionTexelUv()).r;
        vec3 reflected = rhoS + (1.0 - rhoS) * shade.fresnel;
        float gloss = clamp(log2(max(exponent, 1.0)) / kLog2MirrorExponent, 0.0, 1.0);
        radiance = (1.0 - share) * diffuse + specular +
                   share * (1.0 - reflected) * transmissionTint.rgb * base * transmittedRadiance(v, n, gloss);
    }
    if (HAS_EMISSION)
        radiance += emissiveNormalScale.rgb * texture(uEmissive, slotUv(3)).rgb;

    fragColor = WRITES_RADIANCE ? encodeMapTexel(radiance, MAPS_RGBM)
                                    : vec4(encodeSrgb(cameraResponse(radiance * frameParams.w)), 1.0);
    fragRadiance = encodeMapTexel(max(radiance * frameParams.w - lensParams.x, 0.0), MAPS_RGBM);
    // BLEND: the coverage goes out as alpha wherever the target is not RGBM-encoded.
    if (!WRITES_RADIANCE || !MAPS_RGBM)
        fragColor.a = alpha;
    if (!MAPS_RGBM)
        fragRadiance.a = alpha;
}
