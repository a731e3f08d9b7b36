#version 300 es
// glTF metallic-roughness shading under image-based light from the real environment, in
// linear space: diffuse from the environment's SH9 irradiance, specular from the mipmapped
// equirectangular map along the reflection vector times an analytic environment BRDF,
// plus emission; then ACES tone mapping and sRGB encoding for the RGBA8 target.
precision highp float;
precision highp sampler2D;

layout(std140) uniform Frame {
    mat4 clipFromCamera;
    mat3 environmentFromCamera;
    vec4 irradianceSH[9];
    vec4 environmentParams;
};

layout(std140) uniform Material {
    vec4 baseColorFactor;
    vec4 emissiveNormalScale;
    vec4 metallicRoughness;
};

uniform sampler2D uBaseColor;         // sRGB texture: sampled as linear
uniform sampler2D uMetallicRoughness; // g: roughness, b: metallic
uniform sampler2D uNormal;            // tangent space
uniform sampler2D uEmissive;          // sRGB texture: sampled as linear
uniform sampler2D uEnvironment;       // equirectangular linear radiance, mipmapped

in vec3 vPosition;
in vec3 vNormal;
in vec4 vTangent;
in vec2 vUv;

out vec4 fragColor;

const float PI = 3.14159265358979;

// Sum of c'_lm Y_lm(n) with the real SH basis of gles_renderer/environment_map.h (band 1
// ordered y, z, x); the coefficients already hold the cosine-lobe factors / pi.
vec3 diffuseIrradianceOverPi(vec3 n)
{
    vec3 e = irradianceSH[0].rgb * 0.282095;
    e += irradianceSH[1].rgb * (0.488603 * n.y);
    e += irradianceSH[2].rgb * (0.488603 * n.z);
    e += irradianceSH[3].rgb * (0.488603 * n.x);
    e += irradianceSH[4].rgb * (1.092548 * n.x * n.y);
    e += irradianceSH[5].rgb * (1.092548 * n.y * n.z);
    e += irradianceSH[6].rgb * (0.315392 * (3.0 * n.z * n.z - 1.0));
    e += irradianceSH[7].rgb * (1.092548 * n.x * n.z);
    e += irradianceSH[8].rgb * (0.546274 * (n.x * n.x - n.y * n.y));
    return max(e, vec3(0.0));
}

// Direction (environment frame, +y up) to equirectangular uv, v = 0 the top row.
vec2 equirectUv(vec3 d)
{
    return vec2(0.5 + atan(d.z, d.x) / (2.0 * PI), acos(clamp(d.y, -1.0, 1.0)) / PI);
}

// Karis' analytic fit of the split-sum environment BRDF ("Physically Based Shading on
// Mobile", 2014): scale and bias applied to F0.
vec2 environmentBrdf(float roughness, float nDotV)
{
    const vec4 c0 = vec4(-1.0, -0.0275, -0.572, 0.022);
    const vec4 c1 = vec4(1.0, 0.0425, 1.04, -0.04);
    vec4 r = roughness * c0 + c1;
    float a004 = min(r.x * r.x, exp2(-9.28 * nDotV)) * r.x + r.y;
    return vec2(-1.04, 1.04) * a004 + r.zw;
}

// Narkowicz's fit of the ACES filmic curve (exposure 1).
vec3 toneMapAces(vec3 x)
{
    return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

// sRGB encoding of c in [0, 1]. The power 1/2.4 is replaced by Ian Taylor's fit in square
// roots ("sRGB approximations for HLSL", 2012): within 0.25 code values of the exact curve
// at 8 bits, and about 10% of llvmpipe's time for a model filling the frame cheaper.
vec3 encodeSrgb(vec3 c)
{
    vec3 low = c * 12.92;
    vec3 s1 = sqrt(c);
    vec3 s2 = sqrt(s1);
    vec3 s3 = sqrt(s2);
    vec3 high = 0.662002687 * s1 + 0.684122060 * s2 - 0.323583601 * s3 - 0.0225411470 * c;
    return mix(low, high, step(vec3(0.0031308), c));
}

vec3 shadingNormal()
{
    vec3 n = normalize(vNormal);
    vec3 t = vTangent.xyz - n * dot(n, vTangent.xyz);
    // Meshes without usable uvs have no tangent: keep the interpolated normal.
    if (dot(t, t) > 1e-12) {
        t = normalize(t);
        vec3 b = cross(n, t) * (vTangent.w < 0.0 ? -1.0 : 1.0);
        vec3 tangentNormal = texture(uNormal, vUv).xyz * 2.0 - 1.0;
        tangentNormal.xy *= emissiveNormalScale.w;
        n = normalize(mat3(t, b, n) * tangentNormal);
    }
    // Back faces of double-sided materials are lit as seen from their side.
    return gl_FrontFacing ? n : -n;
}

void main()
{
    vec3 baseColor = baseColorFactor.rgb * texture(uBaseColor, vUv).rgb;
    vec3 metallicRoughnessTexel = texture(uMetallicRoughness, vUv).rgb;
    float metallic = clamp(metallicRoughness.x * metallicRoughnessTexel.b, 0.0, 1.0);
    float roughness = clamp(metallicRoughness.y * metallicRoughnessTexel.g, 0.0, 1.0);

    vec3 n = shadingNormal();
    vec3 v = normalize(-vPosition);
    float nDotV = clamp(dot(n, v), 1e-4, 1.0);
    vec3 reflected = reflect(-v, n);

    vec3 diffuse = baseColor * (1.0 - metallic) * diffuseIrradianceOverPi(environmentFromCamera * n);

    vec3 f0 = mix(vec3(0.04), baseColor, metallic);
    vec2 brdf = environmentBrdf(roughness, nDotV);
    // An explicit LOD: implicit derivatives jump across the map's u seam.
    vec3 prefiltered = textureLod(uEnvironment, equirectUv(normalize(environmentFromCamera * reflected)),
                                  roughness * environmentParams.x).rgb;
    vec3 specular = prefiltered * (f0 * brdf.x + brdf.y);

    vec3 emissive = emissiveNormalScale.rgb * texture(uEmissive, vUv).rgb;

    fragColor = vec4(encodeSrgb(toneMapAces(diffuse + specular + emissive)), 1.0);
}
