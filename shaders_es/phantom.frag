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

// A direction's cube face and its face coordinates, found once for all the maps it is looked
// up in (cube_atlas.glsl's cubeBankLevelUv, split at the part that does not depend on the
// map's size): llvmpipe runs every branch of a shader, so each lookup pays in full.
struct CubeFaceHit {
    vec2 cell;
    vec2 st; // unclamped, in [0, 1]
};

CubeFaceHit cubeFaceHit(vec3 d)
{
    vec3 a = abs(d);
    bool xMajor = a.x >= a.y && a.x >= a.z;
    bool yMajor = !xMajor && a.y >= a.z;
    float ma = xMajor ? a.x : (yMajor ? a.y : a.z);
    float positive = xMajor ? d.x : (yMajor ? d.y : d.z);
    float side = positive > 0.0 ? 1.0 : -1.0;
    vec2 cell = xMajor ? vec2(0.0, 0.0) : (yMajor ? vec2(2.0, 0.0) : vec2(1.0, 1.0));
    cell.x += positive > 0.0 ? 0.0 : 1.0;
    CubeFaceHit hit;
    hit.cell = cell.x > 2.5 ? vec2(0.0, 1.0) : cell;
    vec2 sctc = xMajor ? vec2(-side * d.z, -d.y) : (yMajor ? vec2(d.x, side * d.z) : vec2(side * d.x, -d.y));
    hit.st = sctc / (2.0 * ma) + 0.5;
    return hit;
}

// Level 0 of an atlas (one slot) at `hit`, as cubeAtlasUv(d, cubeAtlasSize(map), 0.0) gives it.
vec3 mapRadiance(sampler2D map, CubeFaceHit hit)
{
    CubeBankLevel l = cubeBankLevel(cubeAtlasSize(map), vec2(0.0, 1.0), 0.0);
    vec2 uv = hit.cell * l.cellScale + clamp(hit.st, l.stMin, 1.0 - l.stMin) * l.stScale + l.offset;
    return decodeMapTexel(textureLod(map, uv, 0.0), frameParams.z > 0.5);
}

// mesh.frag's blend of the two maps about glossiness s (glossyBlend), as weights on all
// four maps: four lookups where the branches would run six.
vec3 environmentRadiance(CubeFaceHit hit, float s)
{
    vec2 blend = glossyBlend(s);
    float low = 1.0 - blend.y;
    float wDiffuse = blend.x < 0.5 ? low : 0.0;
    float wGlossy1 = blend.x < 0.5 ? blend.y : (blend.x < 1.5 ? low : 0.0);
    float wGlossy2 = blend.x < 0.5 ? 0.0 : (blend.x < 1.5 ? blend.y : low);
    float wMirror = blend.x < 1.5 ? 0.0 : blend.y;
    return wDiffuse * mapRadiance(uDiffuseMap, hit) + wGlossy1 * mapRadiance(uGlossy1Map, hit) +
           wGlossy2 * mapRadiance(uGlossy2Map, hit) + wMirror * mapRadiance(uMirrorMap, hit);
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
