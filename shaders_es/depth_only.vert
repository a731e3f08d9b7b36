#version 300 es
// Positions only: the phantoms' depth in the frame (the camera image shows the real object).

layout(std140) uniform Frame {
    mat4 clipFromCamera;
    mat3 environmentFromCamera;
    vec4 frameParams;
};

uniform mat4 uCameraFromMesh;

layout(location = 0) in vec3 aPosition;

void main()
{
    gl_Position = clipFromCamera * (uCameraFromMesh * vec4(aPosition, 1.0));
}
