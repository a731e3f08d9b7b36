#version 300 es
// Copies a texture texel for texel (the bound viewport's pixels from the same texels of
// uSource): the backdrop of an object's environment-map atlas, drawn into the atlas it
// will share a framebuffer with. A glCopyTexSubImage2D would drain llvmpipe's rasteriser
// threads first; a draw is binned like any other.
precision highp float;
precision highp sampler2D;

uniform sampler2D uSource;
uniform ivec2 uOffset; // the source texel of fragment p is p - uOffset (a bank slot moved)
out vec4 fragColor;

void main()
{
    fragColor = texelFetch(uSource, ivec2(gl_FragCoord.xy) - uOffset, 0);
}
