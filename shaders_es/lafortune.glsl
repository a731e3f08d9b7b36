// The paper's shading model (DESIGN.md §6.4), shared by mesh.frag and the tests that check
// it against gles_renderer/lafortune_shading.h, its CPU twin: McAllister's one-lobe
// Lafortune SBRDF looked up in prefiltered environment maps, with the per-texel tangent
// rotation and the paper's Fresnel factor f(R) = (1 - R.N)^(1/phi - 1).
const float PI = 3.14159265358979;
// Exponent of the mirror map; glossiness is normalised as log2(n) / log2(kMirrorExponent),
// so the four maps sit at s = 0 (diffuse, n = 1), 1/4 (n = 8), 1/2 (n = 64) and 1 (mirror).
const float kLog2MirrorExponent = 12.0;

// glTF metallic-roughness as Lafortune parameters (gles_renderer/lafortune_material.h, the
// CPU twin): a Phong lobe (C = -1, -1, 1) whose exponent follows the roughness, rho_s the
// dielectric's reflectance at normal incidence blended towards the base colour by metalness.
const float kMaxExponent = 4096.0;
const float kDielectricSpecular = 0.04;

// The Phong exponent of a glTF roughness (alpha = roughness^2, n = 2 / alpha^2 - 2).
float phongExponentFromRoughness(float roughness)
{
    float alpha = max(roughness * roughness, 1e-4);
    return clamp(2.0 / (alpha * alpha) - 2.0, 1.0, kMaxExponent);
}

// The tangent turned about the normal by angle a * pi (a from the tangent-rotation map;
// pi is enough: the lobe is symmetric under T -> -T).
vec3 rotateTangent(vec3 t, vec3 n, float a)
{
    float angle = a * PI;
    return t * cos(angle) + cross(n, t) * sin(angle);
}

struct LafortuneShade {
    vec3 lobeDirection;  // r: unit peak direction of the lobe, in the frame of t, b, n
    float magnitude;     // |C o v|^n, the lobe's value at its peak
    float fresnel;       // f(r)
    float glossiness;    // s' in [0, 1] after Fresnel: selects the maps
    vec3 specularWeight; // rho_s' * magnitude * g', what multiplies the map lookup
};

// What follows from the lobe's direction and magnitude (set in s): the paper's Fresnel factor,
// the glossiness it raises, and the weight on the maps' radiance. Shared by lafortuneShade
// and phongShade.
void finishShade(inout LafortuneShade s, vec3 n, float exponent, vec3 rhoS, float phi)
{
    float cosine = clamp(dot(s.lobeDirection, n), 0.0, 1.0);
    s.fresnel = phi >= 1e-3 ? pow(1.0 - cosine, 1.0 / phi - 1.0) : 0.0;
    float gloss = clamp(log2(max(exponent, 1.0)) / kLog2MirrorExponent, 0.0, 1.0);
    s.glossiness = gloss + (1.0 - gloss) * s.fresnel;
    vec3 rhoSPrime = rhoS + (1.0 - rhoS) * s.fresnel;
    float falloff = cosine + (1.0 - cosine) * s.fresnel;
    s.specularWeight = rhoSPrime * s.magnitude * falloff;
}

// v: unit direction to the viewer; t, b, n: the (rotated) local frame; lobe: C_x, C_y, C_z;
// exponent n >= 1; rhoS: specular albedo; phi in [0, 1) (below 1e-3: no Fresnel).
// rho_s is normalised so that a Phong lobe (C = -1, -1, 1) reflects the fraction rho_s of
// the lobe-averaged radiance that the prefiltered map stores.
LafortuneShade lafortuneShade(vec3 v, vec3 t, vec3 b, vec3 n, vec3 lobe, float exponent, vec3 rhoS, float phi)
{
    vec3 peak = lobe * vec3(dot(v, t), dot(v, b), dot(v, n));
    float len = length(peak);
    LafortuneShade s;
    s.lobeDirection = len > 1e-8 ? (t * peak.x + b * peak.y + n * peak.z) / len : n;
    // exp2 of a clamped log: |C| > 1 with a large n would overflow to infinity.
    s.magnitude = len > 1e-8 ? exp2(min(exponent * log2(len), 4.0)) : 0.0;
    finishShade(s, n, exponent, rhoS, phi);
    return s;
}

// lafortuneShade for the Phong lobe C = (-1, -1, 1), whatever the tangent frame: its peak
// (-v.t, -v.b, v.n) in an orthonormal frame is the mirror direction 2 (v.n) n - v, of length
// |v| = 1, so the magnitude is 1 (lafortuneShade's differ from these by float rounding).
LafortuneShade phongShade(vec3 v, vec3 n, float exponent, vec3 rhoS, float phi)
{
    LafortuneShade s;
    s.lobeDirection = reflect(-v, n);
    s.magnitude = 1.0; // a constant: finishShade's product by it folds away
    finishShade(s, n, exponent, rhoS, phi);
    return s;
}

// Which two maps a normalised glossiness s falls between and the blend weight of the
// second: 0 = diffuse/glossy-1, 1 = glossy-1/glossy-2, 2 = glossy-2/mirror. Linear in s is
// linear in log n: the maps sit at equal steps of log2 n (0, 3, 6, 12).
vec2 glossyBlend(float s)
{
    if (s < 0.25)
        return vec2(0.0, s * 4.0);
    if (s < 0.5)
        return vec2(1.0, (s - 0.25) * 4.0);
    return vec2(2.0, min((s - 0.5) * 2.0, 1.0));
}

// glossyBlend as weights on the four maps (diffuse, glossy-1, glossy-2, mirror): the two
// neighbours weigh 1 - t and t, the others 0. Without branches: llvmpipe runs every side of
// a branch, which made the three pairs six lookups instead of four.
vec4 glossyWeights(float s)
{
    vec2 blend = glossyBlend(s);
    float low = 1.0 - blend.y;
    return vec4(blend.x < 0.5 ? low : 0.0, blend.x < 0.5 ? blend.y : (blend.x < 1.5 ? low : 0.0),
                blend.x < 0.5 ? 0.0 : (blend.x < 1.5 ? blend.y : low), blend.x < 1.5 ? 0.0 : blend.y);
}
