#version 300 es
// The camera image, copied as it is: a pixel no virtual object touches leaves unchanged.
precision mediump float;

uniform sampler2D uCamera;
in vec2 vUv;
out vec4 fragColor;

void main()
{
    fragColor = vec4(texture(uCamera, vUv).rgb, 1.0);
}
