// SH projection with uniformly spaced samples (DESIGN.md §6.2), pass 1 of 2: fragment
// (i, g) sums L(w_k) Y_j(w_k) 4pi/N over the samples of row i of uSamples for the three
// coefficients j = 3g + c, into output c (one fetch of L per sample for three sums);
// sh_reduce.frag adds the rows. Equal weights and no per-texel solid angle: the stage that includes this
// defines radianceAt(d) for its map format (cube, lat-long, ...) and nothing else changes
// (and, defining SH_PREPARE_RADIANCE, a prepareRadiance() run once per fragment first).
uniform sampler2D uSamples; // RGBA32F: xyz a unit direction (environment frame)
uniform float uWeight;      // 4 pi / N
uniform ivec2 uCellOrigin;  // the fragment of (row 0, group 0): a bank slot's sums start there

layout(location = 0) out vec4 fragCoefficient0; // coefficient 3g
layout(location = 1) out vec4 fragCoefficient1; // 3g + 1
layout(location = 2) out vec4 fragCoefficient2; // 3g + 2

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
    int j = 3 * cell.y;
    vec3 a = vec3(kShA[j], kShA[j + 1], kShA[j + 2]);
    // Row c of each matrix is coefficient j + c's (so the three are one matrix product).
    mat3 b = transpose(mat3(kShB[j], kShB[j + 1], kShB[j + 2]));
    mat3 c = transpose(mat3(kShC[j], kShC[j + 1], kShC[j + 2]));
    mat3 e = transpose(mat3(kShE[j], kShE[j + 1], kShE[j + 2]));
    vec3 sum0 = vec3(0.0), sum1 = vec3(0.0), sum2 = vec3(0.0);
#ifdef SH_PREPARE_RADIANCE
    prepareRadiance(); // the including stage's per-fragment constants of radianceAt
#endif
    for (int k = 0; k < perRow; ++k) {
        vec3 d = texelFetch(uSamples, ivec2(k, cell.x), 0).xyz;
        vec3 l = radianceAt(d);
        vec3 y = a + b * d + c * (d * d) + e * (d * d.yzx); // Y_j, Y_j+1, Y_j+2
        sum0 += l * y.x;
        sum1 += l * y.y;
        sum2 += l * y.z;
    }
    fragCoefficient0 = vec4(sum0 * uWeight, 1.0);
    fragCoefficient1 = vec4(sum1 * uWeight, 1.0);
    fragCoefficient2 = vec4(sum2 * uWeight, 1.0);
}
