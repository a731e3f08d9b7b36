// SH projection with uniformly spaced samples (DESIGN.md §6.2), pass 1 of 2: fragment
// (i, j) sums L(w_k) Y_j(w_k) 4pi/N over the samples of row i of uSamples; sh_reduce.frag
// adds the rows. Equal weights and no per-texel solid angle: the stage that includes this
// defines radianceAt(d) for its map format (cube, lat-long, ...) and nothing else changes
// (and, defining SH_PREPARE_RADIANCE, a prepareRadiance() run once per fragment first).
uniform sampler2D uSamples; // RGBA32F: xyz a unit direction (environment frame)
uniform float uWeight;      // 4 pi / N
uniform ivec2 uCellOrigin;  // the fragment of (row 0, coefficient 0): a bank slot's sums start there

out vec4 fragColor;

// sh_basis.glsl's Y_j(d) (its constants: include it first) = a + dot(b, d) + dot(c, d * d) + dot(e, d * d.yzx): basis
// function j's terms picked once per fragment, so the sample loop indexes no array (llvmpipe
// keeps a local array indexed by a non-constant in memory, stored and loaded every sample).
const float kShA[9] = float[9](kSh00, 0.0, 0.0, 0.0, 0.0, 0.0, -kSh20, 0.0, 0.0);
const vec3 kShB[9] = vec3[9](vec3(0.0), vec3(0.0, kSh1, 0.0), vec3(0.0, 0.0, kSh1), vec3(kSh1, 0.0, 0.0), vec3(0.0),
                             vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
const vec3 kShC[9] = vec3[9](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0),
                             vec3(0.0, 0.0, 3.0 * kSh20), vec3(0.0), vec3(kSh22, -kSh22, 0.0));
const vec3 kShE[9] = vec3[9](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(kSh2Mixed, 0.0, 0.0),
                             vec3(0.0, kSh2Mixed, 0.0), vec3(0.0), vec3(0.0, 0.0, kSh2Mixed), vec3(0.0));

void main()
{
    ivec2 cell = ivec2(gl_FragCoord.xy) - uCellOrigin;
    int perRow = textureSize(uSamples, 0).x;
    float a = kShA[cell.y];
    vec3 b = kShB[cell.y], c = kShC[cell.y], e = kShE[cell.y];
    vec3 sum = vec3(0.0);
#ifdef SH_PREPARE_RADIANCE
    prepareRadiance(); // the including stage's per-fragment constants of radianceAt
#endif
    for (int k = 0; k < perRow; ++k) {
        vec3 d = texelFetch(uSamples, ivec2(k, cell.x), 0).xyz;
        sum += radianceAt(d) * (a + dot(b, d) + dot(c, d * d) + dot(e, d * d.yzx));
    }
    fragColor = vec4(sum * uWeight, 1.0);
}
