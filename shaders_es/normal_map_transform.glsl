// A normal map read through KHR_texture_transform: its texels' x and y axes are the directions
// in which the transformed uv' grows (x: +u', y: -v', as glTF's tangent frame is for
// untransformed uvs), not the surface's tangent T and bitangent B. With uv' = A uv + offset,
// A = (a b; c d) by rows (the slot's two uvTransforms rows), the chain rule gives dP/du' and
// -dP/dv' in the (T, B) frame (T = dP/du, B = -dP/dv) as (d, c) and (b, a), each / det A; they
// are made unit length (exact for rotation, uniform scale and mirroring; a non-uniform scale
// is approximated by the directions alone). Identity: (1, 0) and (0, 1), the map as it was.
// Returns the tangent-space xy in the (T, B) frame. A degenerate transform keeps xy.
vec2 normalMapXyInTangentFrame(vec2 xy, vec4 row0, vec4 row1)
{
    float det = row0.x * row1.y - row0.y * row1.x;
    vec2 alongU = vec2(row1.y, row1.x);
    vec2 alongV = vec2(row0.y, row0.x);
    if (abs(det) < 1e-12 || dot(alongU, alongU) < 1e-24 || dot(alongV, alongV) < 1e-24)
        return xy;
    float side = det < 0.0 ? -1.0 : 1.0;
    return side * (xy.x * normalize(alongU) + xy.y * normalize(alongV));
}
