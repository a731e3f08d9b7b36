#version 300 es
// Copies a texture texel for texel (the bound viewport's pixels from the same texels of
// uSource): the backdrop of an object's environment-map atlas, drawn into the atlas it
// will share a framebuffer with. A glCopyTexSubImage2D would drain llvmpipe's rasteriser
// threads first; a draw is binned like any other.
precision highp float;
precision highp sampler2D;

uniform sampler2D uSource;
out vec4 fragColor;

void main()
{
    fragColor = texelFetch(uSource, ivec2(gl_FragCoord.xy), 0);
}
