#version 300 es
// Differential shading of a real surface (DESIGN.md §6.5): the camera already shows it lit by
// the whole environment, E_env; the virtual objects take away part of that light, and the
// camera pixel is multiplied (glBlendFunc(GL_DST_COLOR, GL_ZERO)) by
//   ratio = 1 - Y((1 - visibility) E_L + (1 - openness) E_ambient) / Y(E_env)
// where Y is luminance (Rec. 709): one factor for the three channels. The camera pixel already
// has the real light's colour, and the estimated light's colour is the least certain part of
// the estimate (from the environment's SH: venice_sunset_1k.hdr's light would take 99 % of
// the floor's red and 48 % of its blue, a teal shadow); per channel the ratio would carry
// that error into the hue of every shadow. E_L = lightIrradiance max(0, n.l) (at most E_env) is the dominant light's
// share, E_ambient = E_env - E_L the rest of the sky, visibility the shadow map's, and
// openness the analytic contact occlusion below. The frame holds sRGB-encoded values, and
// encoded(x * r) is close to encoded(x) * r^(1/2.2) (sRGB as a pure 2.2 gamma): the output is
// ratio^(1/2.2). Where nothing darkens the surface the ratio is exactly 1 and the camera pixel
// is unchanged.
precision highp float;
precision highp sampler2D;

// ShadowPass links a variant without the shadow map's lookups (RECEIVER_SHADOW 0) for the
// places no caster's prism along the light reaches, where every lookup would find the light
// unblocked (visibility exactly 1); uOccluder* there hold only the occluders whose reach
// touches the place drawn.
#ifndef RECEIVER_SHADOW
#define RECEIVER_SHADOW 1
#endif
precision highp sampler2DShadow;

layout(std140) uniform Frame {
    mat4 clipFromCamera;
    mat3 environmentFromCamera;
    // x: +1; y: 0 (the frame); z: 1 = the maps are RGBA8 RGBM; w: see mesh.frag.
    vec4 frameParams;
    // The dominant light in this view (gles_renderer/scene/uniform_blocks.h).
    mat4 lightClipFromCamera;
    vec4 lightDirection;  // xyz: towards the light; w: 1 = sample the shadow map
    vec4 lightIrradiance; // rgb: irradiance at normal incidence; w: 1 = a light is set
    vec4 shadowParams;    // x: PCF radius (texels), y: 1 / map size, z: normal offset (metres), w: depth bias
};

uniform sampler2D uDiffuseMap; // E / pi of the real environment, environment frame
uniform sampler2DShadow uShadowMap;

// Contact occlusion: each virtual object as the ellipsoid of its bounding box's volume (the
// box's inscribed ellipsoid grown by (6/pi)^(1/3) = 1.24), given as the affine map taking the
// camera frame to the space where that ellipsoid is the unit sphere, and the map's inverse
// transpose for normals.
const int kMaxOccluders = 16;
uniform int uOccluderCount;
uniform mat4 uUnitFromCamera[kMaxOccluders];
uniform mat3 uUnitNormalFromCamera[kMaxOccluders];
// xyz: the ellipsoid's centre (camera frame); w: the squared radius of a sphere holding its
// reach (kOcclusionReach times its longest semi-axis).
uniform vec4 uOccluderReach[kMaxOccluders];

in vec3 vPosition;
in vec3 vNormal;

out vec4 fragColor;

#include "cube_atlas.glsl"
#include "rgbm.glsl"
#include "shadow.glsl"

const float kPi = 3.14159265;
// Occluders farther than this many radii (in the unit-sphere space) darken nothing: the
// window below takes their term smoothly to exactly zero, so the camera image far from every
// object is untouched.
const float kOcclusionReach = 2.0; // ShadowPass's too (it draws only within reach)

// The fraction of the cosine-weighted sky that stays open. A unit sphere at distance d whose
// centre makes angle theta with the normal blocks cos(theta) / d^2 of the cosine-weighted
// hemisphere while it is wholly above the horizon (the form factor of a sphere; it
// underestimates a sphere cut by the horizon, which the ground's occluders never are near
// their base). The ellipsoid is made a sphere by an affine map, which keeps which directions
// it blocks but not their cosine weights exactly: an approximation, exact for a sphere.
// Several occluders combine as independent coverage, openness = prod(1 - F_i). It treats the
// blocked sky as being as bright as the ambient sky on average (exact under a uniform sky)
// and the object as black (its own reflected light is left out).
float openness(vec3 position, vec3 normal)
{
    float open = 1.0;
    for (int i = 0; i < uOccluderCount; ++i) {
        // A sphere around the reach first: most pixels are far from most objects.
        vec3 fromCentre = position - uOccluderReach[i].xyz;
        if (dot(fromCentre, fromCentre) >= uOccluderReach[i].w)
            continue;
        vec3 q = (uUnitFromCamera[i] * vec4(position, 1.0)).xyz;
        float d2 = dot(q, q);
        if (d2 >= kOcclusionReach * kOcclusionReach)
            continue;
        float blocked = 1.0;
        if (d2 > 1.0) {
            vec3 m = normalize(uUnitNormalFromCamera[i] * normal);
            float cosTheta = dot(m, -q) * inversesqrt(d2);
            float window = clamp((kOcclusionReach * kOcclusionReach - d2) /
                                     (kOcclusionReach * kOcclusionReach - 1.0), 0.0, 1.0);
            blocked = max(cosTheta, 0.0) / d2 * window;
        }
        open *= 1.0 - clamp(blocked, 0.0, 1.0);
    }
    return open;
}

// Whether any occluder's reach sphere holds the point: cheaper than openness(), which is 1
// wherever this is false.
bool nearAnOccluder(vec3 position)
{
    bool near = false;
    for (int i = 0; i < uOccluderCount; ++i) {
        vec3 fromCentre = position - uOccluderReach[i].xyz;
        near = near || dot(fromCentre, fromCentre) < uOccluderReach[i].w;
    }
    return near;
}

void main()
{
    vec3 n = normalize(vNormal);
    if (!gl_FrontFacing)
        n = -n;
    float nl = lightIrradiance.w > 0.5 ? dot(n, lightDirection.xyz) : 0.0;
#if RECEIVER_SHADOW
    vec4 shadowAt = shadowCoordinates(vPosition, n);
    float corners = nl > 0.0 && lightDirection.w > 0.5 && shadowAt.w > 0.5 ? shadowCorners(shadowAt) : 4.0;
#else
    float corners = 4.0;
#endif
    // The cheap tests first, and a discard at the top level of main: llvmpipe runs both sides
    // of every branch (uniform ones too), but stops shading a block of pixels once a discard
    // has killed all of them. Most of a table is neither in a shadow nor near an object, and
    // its pixels are left alone (a blended write of 1.0 would leave them unchanged too).
    if (corners >= 3.999 && !nearAnOccluder(vPosition))
        discard;
    float open = openness(vPosition, n);
#if RECEIVER_SHADOW
    // The four corners are the whole kernel (shadow.glsl): each a bilinear 2 x 2 comparison,
    // together a 4 x 4 texel footprint. The buffer is shaded at a fraction of the frame's
    // resolution, where a texel spans several of the map's, so the penumbra's finer shape
    // between the corners (the five inner taps of a 3 x 3 grid) hardly shows: car.toml,
    // quarter, against nine taps 0.76 % of the frame's pixels change, by at most 10 code
    // values, 7 pixels by more than 8; the receivers' CPU time ~1-2.5 ms less a frame.
    float visibility = corners * 0.25;
#else
    float visibility = 1.0;
#endif
    if (open == 1.0 && visibility == 1.0)
        discard;
    vec3 environment = kPi * decodeMapTexel(textureLod(uDiffuseMap, cubeAtlasUv(environmentFromCamera * n, cubeAtlasSize(uDiffuseMap), 0.0), 0.0),
                                            frameParams.z > 0.5);
    vec3 light = min(lightIrradiance.rgb * max(nl, 0.0), environment);
    const vec3 kLuminance = vec3(0.2126, 0.7152, 0.0722);
    float removed = dot((1.0 - visibility) * light + (1.0 - open) * (environment - light), kLuminance);
    float ratio = clamp(1.0 - removed / max(dot(environment, kLuminance), 1e-6), 0.0, 1.0);
    fragColor = vec4(vec3(pow(ratio, 1.0 / 2.2)), 1.0);
}
