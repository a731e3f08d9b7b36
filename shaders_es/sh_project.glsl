// SH projection with uniformly spaced samples (DESIGN.md §6.2), pass 1 of 2: fragment
// (i, j) sums L(w_k) Y_j(w_k) 4pi/N over the samples of row i of uSamples; sh_reduce.frag
// adds the rows. Equal weights and no per-texel solid angle: the stage that includes this
// defines radianceAt(d) for its map format (cube, lat-long, ...) and nothing else changes
// (and, defining SH_PREPARE_RADIANCE, a prepareRadiance() run once per fragment first).
uniform sampler2D uSamples; // RGBA32F: xyz a unit direction (environment frame)
uniform float uWeight;      // 4 pi / N
uniform ivec2 uCellOrigin;  // the fragment of (row 0, coefficient 0): a bank slot's sums start there

out vec4 fragColor;

void main()
{
    ivec2 cell = ivec2(gl_FragCoord.xy) - uCellOrigin;
    int perRow = textureSize(uSamples, 0).x;
    vec3 sum = vec3(0.0);
#ifdef SH_PREPARE_RADIANCE
    prepareRadiance(); // the including stage's per-fragment constants of radianceAt
#endif
    for (int k = 0; k < perRow; ++k) {
        vec3 d = texelFetch(uSamples, ivec2(k, cell.x), 0).xyz;
        float y[9];
        shBasis(d, y);
        sum += radianceAt(d) * y[cell.y];
    }
    fragColor = vec4(sum * uWeight, 1.0);
}
