#version 300 es
// A phantom (a real object's proxy, DESIGN.md §6.5) inside an environment map's cube face,
// carrying the camera image (§6.1): each fragment is taken into the frame camera's frame and
// projected into this frame's camera image. Where the camera saw the point — in front of it,
// inside the frame, on a side facing it and not hidden from it by another phantom — the
// point's radiance is what the camera measured: the texel linearised from sRGB, divided by
// the exposure (the frame multiplies virtual radiance by it again, and its response is linear
// sRGB below the knee, so a mirror shows the camera's code values). Elsewhere (the back of a
// box, what lies outside the frame or behind another phantom) the phantom keeps its
// configured colour, lit by the real environment's maps as mesh.frag lights it: a plausible
// guess rather than the black or smeared image an unseen point would otherwise get. The two
// blend over a narrow band (frame edge, grazing view, occlusion edge) so the seam does not
// flicker as the camera moves.
//
// Its own program rather than a branch in mesh.frag: a phantom needs none of the material
// textures, normal maps or tangent rotation, and phantom texels are numerous in the maps (a
// table fills a hemisphere of every map), so a lean shader keeps the faces cheap on llvmpipe;
// the camera's uniforms then belong to this program alone.
precision highp float;
precision highp sampler2D;
precision highp sampler2DShadow;

layout(std140) uniform Frame {
    mat4 clipFromCamera; // the cube face's projection
    mat3 environmentFromCamera;
    vec4 frameParams; // x: -1 (mirrored face frame), z: 1 = RGBM maps (mesh.frag)
    // The dominant light (mesh.frag); unused here, declared so the block matches mesh.vert's.
    mat4 lightClipFromCamera;
    vec4 lightDirection;
    vec4 lightIrradiance;
    vec4 shadowParams;
};

// The phantom's material (its baseColorFactor: the configured colour, linear albedo); the
// shared block, of which it reads the first members.
#include "material_block.glsl"

uniform mat4 uFrameCameraFromView;  // the view's (face's) frame to the frame camera's
uniform mat4 uClipFromFrameCamera;  // the frame camera's projection (camera_projection.h)
uniform float uInverseExposure;     // 1 / SceneRenderer::setExposure's scale
uniform sampler2D uCameraImage;     // sRGB-encoded RGBA8, mipmapped, row 0 = image top
uniform sampler2DShadow uCameraDepth; // the phantoms' depth as the frame camera sees them
uniform sampler2D uDiffuseMap;
uniform sampler2D uGlossy1Map;
uniform sampler2D uGlossy2Map;
uniform sampler2D uMirrorMap;

in vec3 vPosition;
in vec3 vNormal;
in vec4 vTangent;
in vec2 vUv;

out vec4 fragColor;

#include "lafortune.glsl"
#include "cube_atlas.glsl"
#include "rgbm.glsl"

const float kMaxExponent = 4096.0;
const float kDielectricSpecular = 0.04;
// Blend bands: cosine of the view from the camera (a side seen at more than ~84 degrees
// shows a smear of a few pixels), and the frame border in texture coordinates.
const float kGrazingCosine = 0.1;
const float kBorder = 0.01;

// Level 0 of an atlas (one slot) at `hit`, as cubeAtlasUv(d, cubeAtlasSize(map), 0.0) gives it.
vec3 mapRadiance(sampler2D map, CubeFaceHit hit)
{
    vec2 uv = cubeHitUv(hit, cubeBankLevel(cubeAtlasSize(map), vec2(0.0, 1.0), 0.0));
    return decodeMapTexel(textureLod(map, uv, 0.0), frameParams.z > 0.5);
}

// mesh.frag's environmentRadiance, from one face hit for the four maps.
vec3 environmentRadiance(CubeFaceHit hit, float s)
{
    vec4 w = glossyWeights(s);
    return w.x * mapRadiance(uDiffuseMap, hit) + w.y * mapRadiance(uGlossy1Map, hit) +
           w.z * mapRadiance(uGlossy2Map, hit) + w.w * mapRadiance(uMirrorMap, hit);
}

// IEC 61966-2-1 sRGB decoding.
vec3 decodeSrgb(vec3 c)
{
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), step(vec3(0.04045), c));
}

// The configured colour lit by the maps, as mesh.frag shades a material without textures.
vec3 configuredRadiance(vec3 n)
{
    vec3 t = normalize(abs(n.x) < 0.9 ? cross(n, vec3(1, 0, 0)) : cross(n, vec3(0, 1, 0)));
    vec3 b = cross(n, t) * frameParams.x;
    vec3 rhoD;
    vec3 rhoS;
    vec3 lobe;
    float exponent;
    if (metallicRoughness.z > 0.5) {
        rhoD = baseColorFactor.rgb;
        rhoS = specularFactor.rgb;
        lobe = lobeFactor.xyz;
        exponent = max(lobeFactor.w, 1.0);
    } else {
        float metallic = clamp(metallicRoughness.x, 0.0, 1.0);
        float alpha = max(metallicRoughness.y * metallicRoughness.y, 1e-4);
        rhoD = baseColorFactor.rgb * (1.0 - metallic);
        rhoS = mix(vec3(kDielectricSpecular), baseColorFactor.rgb, metallic);
        lobe = vec3(-1.0, -1.0, 1.0);
        exponent = clamp(2.0 / (alpha * alpha) - 2.0, 1.0, kMaxExponent);
    }
    LafortuneShade shade = lafortuneShade(normalize(-vPosition), t, b, n, lobe, exponent, rhoS, metallicRoughness.w);
    return rhoD * mapRadiance(uDiffuseMap, cubeFaceHit(environmentFromCamera * n)) +
           shade.specularWeight *
               environmentRadiance(cubeFaceHit(environmentFromCamera * shade.lobeDirection), shade.glossiness) +
           emissiveNormalScale.rgb;
}

void main()
{
    vec3 n = normalize(vNormal);
    if (!gl_FrontFacing)
        n = -n;

    // Where the frame camera saw this point. The lookup runs for every fragment, before any
    // branch, so its implicit derivatives pick the mip level that matches the face texel's
    // footprint in the camera image (no aliasing or shimmer in reflections).
    vec3 p = (uFrameCameraFromView * vec4(vPosition, 1.0)).xyz;
    vec4 clip = uClipFromFrameCamera * vec4(p, 1.0);
    float w = max(clip.w, 1e-6);
    vec3 window = clip.xyz / w * 0.5 + 0.5;
    vec3 seen = decodeSrgb(texture(uCameraImage, window.xy).rgb) * uInverseExposure;

    vec3 normalInCamera = mat3(uFrameCameraFromView) * n;
    float facing = dot(normalInCamera, normalize(-p));
    vec2 inside = min(window.xy, 1.0 - window.xy);
    float weight = step(1e-6, clip.w) * smoothstep(0.0, kGrazingCosine, facing) *
                   smoothstep(0.0, kBorder, min(inside.x, inside.y));
    // The phantoms' depth was drawn with a slope-scaled offset, so the surface the camera saw
    // passes; linear filtering gives a soft edge behind an occluding phantom.
    if (weight > 0.0)
        weight *= textureLod(uCameraDepth, vec3(window.xy, window.z), 0.0);

    vec3 radiance = seen;
    if (weight < 1.0)
        radiance = mix(configuredRadiance(n), seen, weight);
    fragColor = encodeMapTexel(radiance, frameParams.z > 0.5);
}
