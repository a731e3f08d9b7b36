// The dominant light's shadow map (DESIGN.md §6.5; gles_renderer/scene/shadow_pass.h): its
// visibility at a point of the view, for stages whose Frame block has the light's members
// (lightClipFromCamera, lightDirection, lightIrradiance, shadowParams) and that declare
// uShadowMap.
//
// PCF: taps spanning +-softness texels, each a bilinear 2 x 2 comparison (GL_LINEAR with
// GL_COMPARE_REF_TO_TEXTURE), so the penumbra is a smooth ramp about 2 * softness + 1 texels
// wide. Both users take the four corners of a 3 x 3 grid, which have the nine taps' reach:
// the real surfaces (phantom_receiver.frag) discard the pixels the corners find all lit (and
// no contact reaches) before their other work, and llvmpipe then skips them; the virtual
// objects (mesh.frag) pay every tap at every pixel, since llvmpipe runs both sides of a branch
// (the five taps they took until issue 18 were 28 % of their time on the car scene). Against
// nine taps, or the corners and the centre, the penumbra differs by a few code values (the car
// frame: at most 10, on under 1 % of its pixels, all in penumbrae). (An occluder thinner than
// the kernel that slips between its taps is missed: below 2 * softness texels.) A point
// outside the map's frustum is lit: the map
// covers every caster, and a point no caster lies between it and the light cannot be
// shadowed.

// The point's shadow map coordinates: xy the texel position, z the depth to compare, w 1
// where the map's frustum holds the point (else 0: lit).
vec4 shadowCoordinates(vec3 position, vec3 normal)
{
    // Normal offset (shadowParams.z: about one and a half texels) on top of the pass's
    // slope-scaled depth offset: curved and grazing surfaces do not shadow themselves (acne).
    vec3 p = position + normal * shadowParams.z;
    vec3 uvz = (lightClipFromCamera * vec4(p, 1.0)).xyz * 0.5 + 0.5;
    bool inside = all(greaterThanEqual(uvz, vec3(0.0))) && all(lessThanEqual(uvz, vec3(1.0)));
    return vec4(uvz.xy, uvz.z - shadowParams.w, inside ? 1.0 : 0.0);
}

// shadowCoordinates from the parts a vertex shader can interpolate (mesh.vert): `centre`, the
// position's map coordinates ((lightClipFromCamera p).xyz * 0.5 + 0.5), and `normalOffset`,
// what the normal offset adds to them (0.5 * mat3(lightClipFromCamera) * offset * normal). The
// light's projection is orthographic, so both are affine in the vertex's position and normal:
// interpolated, they are the pixel's.
vec4 shadowCoordinatesInterpolated(vec3 centre, vec3 normalOffset)
{
    vec3 uvz = centre + normalOffset;
    bool inside = all(greaterThanEqual(uvz, vec3(0.0))) && all(lessThanEqual(uvz, vec3(1.0)));
    return vec4(uvz.xy, uvz.z - shadowParams.w, inside ? 1.0 : 0.0);
}

// The kernel's four corners (0 to 4 lit): where they agree (all lit or all shadowed:
// everywhere but a penumbra a few texels wide) they are the answer.
float shadowCorners(vec4 coordinates)
{
    vec2 spacing = vec2(shadowParams.x * shadowParams.y);
    return texture(uShadowMap, vec3(coordinates.xy + vec2(-1.0, -1.0) * spacing, coordinates.z)) +
           texture(uShadowMap, vec3(coordinates.xy + vec2(1.0, -1.0) * spacing, coordinates.z)) +
           texture(uShadowMap, vec3(coordinates.xy + vec2(-1.0, 1.0) * spacing, coordinates.z)) +
           texture(uShadowMap, vec3(coordinates.xy + vec2(1.0, 1.0) * spacing, coordinates.z));
}

// The kernel's four corners alone, averaged. Their penumbra is the nine taps' wide, in two
// steps of a half.
float shadowVisibilityFourTapsAt(vec4 coordinates)
{
    return coordinates.w < 0.5 ? 1.0 : shadowCorners(coordinates) * 0.25;
}

float shadowVisibilityFourTaps(vec3 position, vec3 normal)
{
    return shadowVisibilityFourTapsAt(shadowCoordinates(position, normal));
}
