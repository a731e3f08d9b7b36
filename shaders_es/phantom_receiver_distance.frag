#version 300 es
// A receiver's distance from the camera into ShadowPass's darkening buffer (green and blue;
// receiver_distance.glsl), with red (the ratio, which the darkening multiplies next) and alpha
// (the coverage) 1 where a receiver is: where the buffer is shaded at a fraction of the frame's
// resolution, the apply pass takes each pixel's darkening only from the texels of its own
// surface, so a shadow on the table does not bleed onto the real box standing in front of it.
precision highp float;

in vec3 vPosition;
in vec3 vNormal;

out vec4 fragColor;

#include "receiver_distance.glsl"

void main()
{
    fragColor = vec4(1.0, encodeDistance(vPosition), 1.0);
}
