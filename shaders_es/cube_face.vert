#version 300 es
// A single triangle covering one cube-map face (no vertex buffer). vFaceDirection is the
// direction through the fragment in the face camera's frame (x along s, y along t, z the
// face's major axis), so uEnvironmentFromFace * vFaceDirection is the cube-map direction.
out vec3 vFaceDirection;

void main()
{
    vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2)) * 2.0 - 1.0;
    vFaceDirection = vec3(corner, 1.0);
    gl_Position = vec4(corner, 0.0, 1.0);
}
