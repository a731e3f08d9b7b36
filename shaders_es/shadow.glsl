// The dominant light's shadow map (DESIGN.md §6.5; gles_renderer/scene/shadow_pass.h): its
// visibility at a point of the view, for stages whose Frame block has the light's members
// (lightClipFromCamera, lightDirection, lightIrradiance, shadowParams) and that declare
// uShadowMap.
//
// PCF: a 3 x 3 grid of taps spanning +-softness texels, each a bilinear 2 x 2 comparison
// (GL_LINEAR with GL_COMPARE_REF_TO_TEXTURE), so the penumbra is a smooth ramp about
// 2 * softness + 1 texels wide. (An occluder thinner than the kernel that slips between its
// four corners is missed: below 2 * softness texels.) A point outside the map's frustum is lit: the map covers every
// caster, and a point no caster lies between it and the light cannot be shadowed.
float shadowVisibility(vec3 position, vec3 normal)
{
    // Normal offset (about one and a half texels) on top of the pass's slope-scaled depth
    // offset: curved and grazing surfaces do not shadow themselves (acne).
    vec3 p = position + normal * (shadowParams.z * 1.5);
    vec3 uvz = (lightClipFromCamera * vec4(p, 1.0)).xyz * 0.5 + 0.5;
    if (any(lessThan(uvz, vec3(0.0))) || any(greaterThan(uvz, vec3(1.0))))
        return 1.0;
    float reference = uvz.z - shadowParams.w;
    vec2 spacing = vec2(shadowParams.x * shadowParams.y);
    // The kernel's four corners first: where they agree (all lit or all shadowed: everywhere
    // but a penumbra a few texels wide) they are the answer, for four taps instead of nine.
    float corners = texture(uShadowMap, vec3(uvz.xy + vec2(-1.0, -1.0) * spacing, reference)) +
                    texture(uShadowMap, vec3(uvz.xy + vec2(1.0, -1.0) * spacing, reference)) +
                    texture(uShadowMap, vec3(uvz.xy + vec2(-1.0, 1.0) * spacing, reference)) +
                    texture(uShadowMap, vec3(uvz.xy + vec2(1.0, 1.0) * spacing, reference));
    if (corners >= 3.999)
        return 1.0;
    if (corners <= 0.001)
        return 0.0;
    float sum = corners;
    for (int j = -1; j <= 1; ++j)
        for (int i = -1; i <= 1; ++i)
            if (i == 0 || j == 0)
                sum += texture(uShadowMap, vec3(uvz.xy + vec2(float(i), float(j)) * spacing, reference));
    return sum / 9.0;
}
