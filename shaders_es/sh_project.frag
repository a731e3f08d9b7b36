#version 300 es
// SH projection with uniformly spaced samples (DESIGN.md §6.2), pass 1 of 2: fragment
// (i, j) sums L(w_k) Y_j(w_k) 4pi/N over the samples of row i of uSamples; sh_reduce.frag
// adds the rows. Equal weights: no per-texel solid angle, so any map format works.
precision highp float;
precision highp sampler2D;
precision highp samplerCube;

uniform samplerCube uEnvironment;
uniform sampler2D uSamples; // RGBA32F: xyz a unit direction (environment frame)
uniform float uLod;         // the mip level whose texels are about a sample's solid angle
uniform float uWeight;      // 4 pi / N

out vec4 fragColor;

#include "sh_basis.glsl"

void main()
{
    ivec2 cell = ivec2(gl_FragCoord.xy);
    int perRow = textureSize(uSamples, 0).x;
    vec3 sum = vec3(0.0);
    for (int k = 0; k < perRow; ++k) {
        vec3 d = texelFetch(uSamples, ivec2(k, cell.x), 0).xyz;
        float y[9];
        shBasis(d, y);
        sum += textureLod(uEnvironment, d, uLod).rgb * y[cell.y];
    }
    fragColor = vec4(sum * uWeight, 1.0);
}
