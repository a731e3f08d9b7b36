#version 300 es
// A glTF primitive moved into the view's camera frame (the OpenCV camera of the frame, or a
// cube-face camera of an environment map), where mesh.frag shades it, and on to clip space.

layout(std140) uniform Frame {
    mat4 clipFromCamera;
    mat3 environmentFromCamera;
    vec4 frameParams;
    mat4 lightClipFromCamera;
    vec4 lightDirection;
    vec4 lightIrradiance;
    vec4 shadowParams;
    vec4 lensParams;
};

uniform mat4 uCameraFromMesh;
// Inverse transpose of uCameraFromMesh's 3x3 part (normals under non-uniform scale).
uniform mat3 uNormalFromMesh;

layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec2 aUv;
layout(location = 3) in vec4 aTangent;
// glTF COLOR_0 and TEXCOORD_1; constant white and (0, 0) where the primitive has none.
layout(location = 4) in vec4 aColor;
layout(location = 5) in vec2 aUv1;

out vec3 vPosition;
out vec3 vNormal;
out vec4 vTangent;
out vec2 vUv;
out vec4 vColor;
out vec2 vUv1;
// The position in the dominant light's shadow map (xy the texel position, z the depth, all
// in [0, 1] inside its frustum; shadow.glsl), and what the normal offset adds there per unit
// of the interpolated normal vNormal. The light's projection is orthographic (affine), so
// these interpolate to exactly what mesh.frag would compute from vPosition and vNormal per
// pixel (shadowCoordinatesInterpolated), 19 multiply-adds a pixel fewer. Unused (and removed
// by the linker) where mesh.frag reads no shadow.
out vec3 vShadowCentre;
out vec3 vShadowNormal;

void main()
{
    vec4 position = uCameraFromMesh * vec4(aPosition, 1.0);
    vPosition = position.xyz;
    vNormal = uNormalFromMesh * aNormal;
    vTangent = vec4(mat3(uCameraFromMesh) * aTangent.xyz, aTangent.w);
    vUv = aUv;
    vColor = aColor;
    vUv1 = aUv1;
    gl_Position = clipFromCamera * position;
    vShadowCentre = (lightClipFromCamera * position).xyz * 0.5 + 0.5;
    vShadowNormal = mat3(lightClipFromCamera) * vNormal * (0.5 * shadowParams.z);
}
