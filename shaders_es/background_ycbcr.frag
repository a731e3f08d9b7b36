#version 300 es
// The camera image from its YCbCr planes, converted as the CPU converter does, so a pixel no
// virtual object touches comes out as the CPU path would have drawn it (within one code value).
// NV12: uLuma is the Y plane (R8), uChroma the half-size Cb Cr plane (RG8). YUYV: uChroma is
// the packed rows as RGBA8 of half the width (Y0 Cb Y1 Cr), uLuma unused. Chroma is
// replicated over the pixels it covers (texel x/2, and row y/2 for NV12), like the CPU code.
// Image row y is framebuffer row y (see background.frag), so texelFetch addresses both.
precision highp float;
precision highp int;
precision highp sampler2D;

uniform sampler2D uLuma;
uniform sampler2D uChroma;
uniform int uLayout; // 0: NV12, 1: YUYV
uniform bool uBt709;
uniform bool uFullRange;
out vec4 fragColor;

#include "ycbcr.glsl"

void main()
{
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    float y;
    vec2 cbCr;
    if (uLayout == 0) {
        y = texelFetch(uLuma, pixel, 0).r;
        cbCr = texelFetch(uChroma, pixel / 2, 0).rg;
    } else {
        vec4 pair = texelFetch(uChroma, ivec2(pixel.x / 2, pixel.y), 0);
        y = (pixel.x & 1) == 0 ? pair.r : pair.b;
        cbCr = pair.ga;
    }
    // Texels are code / 255; back to exact code values before the conversion.
    vec3 rgb = ycbcrToRgb(round(y * 255.0), round(cbCr.x * 255.0), round(cbCr.y * 255.0), uBt709, uFullRange);
    fragColor = vec4(clamp(rgb / 255.0, 0.0, 1.0), 1.0);
}
