// Shared by the lens-effect passes (gles_renderer/scene/lens_effects.h): texels of the HDR
// images, RGBA16F linear radiance or RGBA8 RGBM where no float format renders (rgbm.glsl),
// fetched with zero outside the image so that sums over an image (the energy the effects
// conserve) do not count edge texels twice.
vec3 fetchRadiance(sampler2D image, ivec2 p, bool rgbm)
{
    ivec2 size = textureSize(image, 0);
    if (any(lessThan(p, ivec2(0))) || any(greaterThanEqual(p, size)))
        return vec3(0.0);
    return decodeMapTexel(texelFetch(image, p, 0), rgbm);
}

// Bilinear interpolation at `coordinate` (texels, centres at +0.5), clamped to the edge: by the
// texture unit for float images (a quarter of the time on llvmpipe), by hand for RGBM, which
// cannot be filtered before it is decoded.
vec3 sampleRadiance(sampler2D image, vec2 coordinate, bool rgbm)
{
    if (!rgbm)
        return textureLod(image, coordinate / vec2(textureSize(image, 0)), 0.0).rgb;
    ivec2 last = textureSize(image, 0) - 1;
    vec2 t = coordinate - 0.5;
    vec2 f = fract(t);
    ivec2 p = ivec2(floor(t));
    vec3 a = decodeMapTexel(texelFetch(image, clamp(p, ivec2(0), last), 0), rgbm);
    vec3 b = decodeMapTexel(texelFetch(image, clamp(p + ivec2(1, 0), ivec2(0), last), 0), rgbm);
    vec3 c = decodeMapTexel(texelFetch(image, clamp(p + ivec2(0, 1), ivec2(0), last), 0), rgbm);
    vec3 d = decodeMapTexel(texelFetch(image, clamp(p + ivec2(1, 1), ivec2(0), last), 0), rgbm);
    return mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
}
