#version 300 es
// A phantom (or a receiver-only ground plane) in the frame (DESIGN.md §6.5): its surface in the
// camera frame, where phantom_receiver.frag works out how much the virtual objects darken the
// real surface the camera image shows there.

layout(std140) uniform Frame {
    mat4 clipFromCamera;
    mat3 environmentFromCamera;
    vec4 frameParams;
    mat4 lightClipFromCamera;
    vec4 lightDirection;
    vec4 lightIrradiance;
    vec4 shadowParams;
};

uniform mat4 uCameraFromMesh;
uniform mat3 uNormalFromMesh;

layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;

out vec3 vPosition;
out vec3 vNormal;

// Phantoms are drawn twice, into depth (with depth_only.frag) and then darkened where their
// depth is equal: both programs must compute the same positions.
invariant gl_Position;

void main()
{
    vec4 position = uCameraFromMesh * vec4(aPosition, 1.0);
    vPosition = position.xyz;
    vNormal = uNormalFromMesh * aNormal;
    gl_Position = clipFromCamera * position;
}
