#version 300 es
// A phantom (a real object's proxy, DESIGN.md §6.5) inside an environment map's cube face,
// carrying the camera image (§6.1): each fragment is taken into the frame camera's frame and
// projected into this frame's camera image. Where the camera saw the point — in front of it,
// inside the frame, on a side facing it and not hidden from it by another phantom — the
// point's radiance is what the camera measured: the texel linearised from sRGB, divided by
// the exposure (the frame multiplies virtual radiance by it again, and its response is linear
// sRGB below the knee, so a mirror shows the camera's code values). Elsewhere (the back of a
// box, what lies outside the frame or behind another phantom) the phantom keeps its
// configured colour, lit by the real environment's maps as mesh.frag lights it (per vertex,
// phantom.vert): a plausible guess rather than the black or smeared image an unseen point
// would otherwise get. The two blend over a narrow band (frame edge, grazing view, occlusion
// edge) so the seam does not flicker as the camera moves.
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

uniform float uInverseExposure;       // 1 / SceneRenderer::setExposure's scale
uniform sampler2D uCameraImage;       // sRGB-encoded RGBA8, mipmapped, row 0 = image top
uniform sampler2DShadow uCameraDepth; // the phantoms' depth as the frame camera sees them

// phantom.vert's: the point and its normal as the frame camera sees them, and the configured
// colour lit by the maps (per vertex: it only counts where the camera did not see the point).
in vec4 vFrameClip;
in vec3 vFramePosition;
in vec3 vFrameNormal;
in vec3 vConfiguredFront;
in vec3 vConfiguredBack;

out vec4 fragColor;

#include "rgbm.glsl"

// Blend bands: cosine of the view from the camera (a side seen at more than ~84 degrees
// shows a smear of a few pixels), and the frame border in texture coordinates.
const float kGrazingCosine = 0.1;
const float kBorder = 0.01;

// IEC 61966-2-1 sRGB decoding.
vec3 decodeSrgb(vec3 c)
{
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), step(vec3(0.04045), c));
}

void main()
{
    vec3 n = normalize(vFrameNormal);
    if (!gl_FrontFacing)
        n = -n;

    // Where the frame camera saw this point. The lookup runs for every fragment, before any
    // branch, so its implicit derivatives pick the mip level that matches the face texel's
    // footprint in the camera image (no aliasing or shimmer in reflections).
    float w = max(vFrameClip.w, 1e-6);
    vec3 window = vFrameClip.xyz / w * 0.5 + 0.5;
    vec3 seen = decodeSrgb(texture(uCameraImage, window.xy).rgb) * uInverseExposure;

    float facing = dot(n, normalize(-vFramePosition));
    vec2 inside = min(window.xy, 1.0 - window.xy);
    float weight = step(1e-6, vFrameClip.w) * smoothstep(0.0, kGrazingCosine, facing) *
                   smoothstep(0.0, kBorder, min(inside.x, inside.y));
    // The phantoms' depth was drawn with a slope-scaled offset, so the surface the camera saw
    // passes; linear filtering gives a soft edge behind an occluding phantom.
    if (weight > 0.0)
        weight *= textureLod(uCameraDepth, vec3(window.xy, window.z), 0.0);

    vec3 configured = gl_FrontFacing ? vConfiguredFront : vConfiguredBack;
    fragColor = encodeMapTexel(mix(configured, seen, weight), frameParams.z > 0.5);
}
