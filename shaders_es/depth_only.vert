#version 300 es
// Positions only: the phantoms' depth in the frame (the camera image shows the real object),
// and the shadow map's casters. With ALPHA_CUTOUT also the uvs and vertex colour that
// depth_only.frag cuts a MASK material by.

layout(std140) uniform Frame {
    mat4 clipFromCamera;
    mat3 environmentFromCamera;
    vec4 frameParams;
};

uniform mat4 uCameraFromMesh;

layout(location = 0) in vec3 aPosition;
#ifdef ALPHA_CUTOUT
layout(location = 2) in vec2 aUv;
layout(location = 4) in vec4 aColor; // constant white where the primitive has no COLOR_0
layout(location = 5) in vec2 aUv1;
out vec2 vUv;
out vec2 vUv1;
out vec4 vColor;
#endif

void main()
{
#ifdef ALPHA_CUTOUT
    vUv = aUv;
    vUv1 = aUv1;
    vColor = aColor;
#endif
    gl_Position = clipFromCamera * (uCameraFromMesh * vec4(aPosition, 1.0));
}
