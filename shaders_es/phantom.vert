#version 300 es
// phantom.frag's vertex stage: a phantom's vertex in the view's (a cube face's) camera frame,
// and what the fragments need of it, per vertex wherever that is exact or good enough.
//
// Exact: the vertex in the frame camera's frame and clip space, and its normal there. The
// view's frame reaches the frame camera's by a rigid motion and the camera's projection is a
// matrix, so the perspective-correct interpolation of these equals what the fragment would
// compute from its interpolated position and normal (two 4 x 4 products a texel fewer).
//
// Approximate: the configured colour lit by the maps (configuredRadiance), the radiance of the
// points the camera did not see. llvmpipe runs both sides of a branch, so evaluated per
// fragment its five map lookups and the Lafortune shade were paid by every phantom texel,
// seen or not (a third of the phantoms' cost in the maps). Per vertex the diffuse term is
// exact on a flat face (one normal) and smooth elsewhere; the specular term is interpolated
// between the vertices' lobes, so on a large face it loses the environment's detail in the
// reflection (a blend of the environment's colours rather than an image of it). That is the
// guess for unseen parts, where no measured radiance exists to compare with.
precision highp float;
precision highp sampler2D;

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

// The phantom's material (its baseColorFactor: the configured colour, linear albedo).
#include "material_block.glsl"

uniform mat4 uCameraFromMesh;
// Inverse transpose of uCameraFromMesh's 3x3 part (normals under non-uniform scale).
uniform mat3 uNormalFromMesh;
uniform mat4 uFrameCameraFromView; // the view's (face's) frame to the frame camera's: rigid
uniform mat4 uClipFromFrameCamera; // the frame camera's projection (camera_projection.h)
uniform sampler2D uDiffuseMap;
uniform sampler2D uGlossy1Map;
uniform sampler2D uGlossy2Map;
uniform sampler2D uMirrorMap;

layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;

out vec4 vFrameClip;       // the point in the frame camera's clip space
out vec3 vFramePosition;   // the point in the frame camera's frame
out vec3 vFrameNormal;     // its normal there (not unit)
out vec3 vConfiguredFront; // configuredRadiance of the front side
out vec3 vConfiguredBack;  // and of the back (double-sided phantoms), normal reversed

#include "lafortune.glsl"
#include "cube_atlas.glsl"
#include "rgbm.glsl"

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

// The configured colour lit by the maps, as mesh.frag shades a material without textures,
// for unit normal n and unit direction v to the viewer.
vec3 configuredRadiance(vec3 n, vec3 v)
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
        rhoD = baseColorFactor.rgb * (1.0 - metallic);
        rhoS = mix(vec3(kDielectricSpecular), baseColorFactor.rgb, metallic);
        lobe = vec3(-1.0, -1.0, 1.0);
        exponent = phongExponentFromRoughness(metallicRoughness.y);
    }
    LafortuneShade shade = lafortuneShade(v, t, b, n, lobe, exponent, rhoS, metallicRoughness.w);
    return rhoD * mapRadiance(uDiffuseMap, cubeFaceHit(environmentFromCamera * n)) +
           shade.specularWeight *
               environmentRadiance(cubeFaceHit(environmentFromCamera * shade.lobeDirection), shade.glossiness) +
           emissiveNormalScale.rgb;
}

void main()
{
    vec4 position = uCameraFromMesh * vec4(aPosition, 1.0);
    vec3 normal = normalize(uNormalFromMesh * aNormal);
    gl_Position = clipFromCamera * position;

    vec4 framePosition = uFrameCameraFromView * position;
    vFramePosition = framePosition.xyz;
    vFrameClip = uClipFromFrameCamera * framePosition;
    vFrameNormal = mat3(uFrameCameraFromView) * normal;

    vec3 v = normalize(-position.xyz);
    vConfiguredFront = configuredRadiance(normal, v);
    vConfiguredBack = configuredRadiance(-normal, v);
}
