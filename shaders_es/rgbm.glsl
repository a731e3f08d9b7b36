// RGBM: HDR radiance in an RGBA8 texel, for GLES implementations that cannot render to any
// float format (the environment maps' fallback). rgb = radiance / (M * range), alpha = M,
// M rounded up to a whole 8-bit step so no channel overflows. Radiance above kRgbmRange
// clips; 8-bit steps cost about 0.4 % of M * range.
const float kRgbmRange = 16.0;

vec4 encodeRgbm(vec3 radiance)
{
    float m = clamp(max(max(radiance.r, radiance.g), max(radiance.b, 1e-6)) / kRgbmRange, 1.0 / 255.0, 1.0);
    m = ceil(m * 255.0) / 255.0;
    return vec4(clamp(radiance / (m * kRgbmRange), 0.0, 1.0), m);
}

vec3 decodeRgbm(vec4 texel)
{
    return texel.rgb * (texel.a * kRgbmRange);
}

// A face's output: RGBM when `rgbm` is set, else linear radiance (RGBA16F).
vec4 encodeMapTexel(vec3 radiance, bool rgbm)
{
    return rgbm ? encodeRgbm(radiance) : vec4(radiance, 1.0);
}

// A map lookup's radiance, decoding RGBM when `rgbm` is set.
vec3 decodeMapTexel(vec4 texel, bool rgbm)
{
    return rgbm ? decodeRgbm(texel) : texel.rgb;
}
