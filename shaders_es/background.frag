#version 300 es
// The camera image, copied as it is: a pixel no virtual object touches leaves unchanged.
// The renderer keeps image row y in framebuffer row y (it draws "upside down" so that
// glReadPixels returns row 0 first), so texel (x, y) goes to fragment (x, y): texelFetch
// with no filtering makes the copy bit-exact.
precision highp float;
precision highp sampler2D;

uniform sampler2D uCamera;
out vec4 fragColor;

void main()
{
    fragColor = vec4(texelFetch(uCamera, ivec2(gl_FragCoord.xy), 0).rgb, 1.0);
}
