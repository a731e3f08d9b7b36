// Cube map lookups in a 2D atlas: the six faces of an environment map side by side in 3
// columns x 2 rows of cells (face f at column f % 3, row f / 3, row 0 at t = 0), as
// IblPipeline renders them (gles_renderer/ibl_gpu/ibl_maps.h). A cell is as high as a face
// and at least 64 px wide (llvmpipe's tile: faces in tiles of their own are rasterised by
// both threads), the face at its left; both sizes follow from the atlas's size. A cube
// texture would need a copy of every face out of the atlas the faces are rendered in, and
// llvmpipe drains its rasteriser threads before each copy; sampling the atlas needs none.
//
// Face selection and (s, t) are GLES 3.0's (§3.8.10, table 3.21), the major axis chosen
// as gles_renderer/ibl/cube_map.h does (the first of x, y, z on ties), so images are those
// of the cube texture. Unlike GLES 3.0's seamless cube filtering, the bilinear footprint
// stays inside the face: (s, t) is clamped half a texel inside it, so no texel of a
// neighbouring cell is read (cube_map.h's sampleCubeBilinear does the same on the CPU).

// The size of an atlas's base level (the level a lookup at lod 0 reads).
vec2 cubeAtlasSize(sampler2D atlas)
{
    return vec2(textureSize(atlas, 0));
}

// A lookup in one slot of a bank at one level, in two parts: what does not depend on the
// direction (cubeBankLevel), computed once by loops of lookups (the SH projection, the glossy
// prefilter: llvmpipe's JIT keeps uniform arithmetic inside a loop), and the face selection,
// the clamp and uv = cell * cellScale + st * stScale + offset (cubeBankLevelUv).
struct CubeBankLevel {
    vec2 cellScale;
    vec2 stScale;
    vec2 offset;
    float stMin; // the clamp: half a texel of the level
};

CubeBankLevel cubeBankLevel(vec2 bankSize, vec2 slot, float lod)
{
    float faceSize = bankSize.y / slot.y * 0.5;
    CubeBankLevel l;
    l.cellScale = vec2(1.0 / 3.0, 0.5 / slot.y);
    l.stScale = vec2(faceSize / bankSize.x, 0.5 / slot.y);
    l.offset = vec2(0.0, slot.x / slot.y);
    l.stMin = 0.5 / max(faceSize * exp2(-lod), 1.0);
    return l;
}

// A direction's cube face (its cell) and face coordinates (s, t) in [0, 1], unclamped: the part
// of a lookup that depends on neither the map nor its level, so a shader that looks one
// direction up in several maps finds the face once (llvmpipe runs every branch of a shader,
// so each lookup would pay for it in full).
struct CubeFaceHit {
    vec2 cell;
    vec2 st;
};

CubeFaceHit cubeFaceHit(vec3 d)
{
    vec3 a = abs(d);
    bool xMajor = a.x >= a.y && a.x >= a.z;
    bool yMajor = !xMajor && a.y >= a.z;
    float ma = xMajor ? a.x : (yMajor ? a.y : a.z);
    float positive = xMajor ? d.x : (yMajor ? d.y : d.z);
    float side = positive > 0.0 ? 1.0 : -1.0;
    // Face f's cell (f % 3, f / 3), f = 0 +X, 1 -X, 2 +Y, 3 -Y, 4 +Z, 5 -Z.
    vec2 cell = xMajor ? vec2(0.0, 0.0) : (yMajor ? vec2(2.0, 0.0) : vec2(1.0, 1.0));
    cell.x += positive > 0.0 ? 0.0 : 1.0;
    CubeFaceHit hit;
    hit.cell = cell.x > 2.5 ? vec2(0.0, 1.0) : cell;
    vec2 sctc = xMajor ? vec2(-side * d.z, -d.y) : (yMajor ? vec2(d.x, side * d.z) : vec2(side * d.x, -d.y));
    hit.st = sctc / (2.0 * ma) + 0.5;
    return hit;
}

// The atlas coordinates of a face hit at one level of one slot: the clamp, then
// uv = cell * cellScale + st * stScale + offset.
vec2 cubeHitUv(CubeFaceHit hit, CubeBankLevel l)
{
    return hit.cell * l.cellScale + clamp(hit.st, l.stMin, 1.0 - l.stMin) * l.stScale + l.offset;
}

vec2 cubeBankLevelUv(vec3 d, CubeBankLevel l)
{
    return cubeHitUv(cubeFaceHit(d), l);
}

// Atlas coordinates of direction d (need not be unit) in slot slot.x of a bank of slot.y
// atlases stacked bottom to top (gles_renderer/ibl_gpu/ibl_maps.h): bankSize is the whole
// texture's size at level 0 (textureSize(bank, 0)), for a lookup at mip level lod (the clamp
// is half a texel of that level). Mipmapped atlases have cells as wide as their faces.
vec2 cubeBankUv(vec3 d, vec2 bankSize, vec2 slot, float lod)
{
    return cubeBankLevelUv(d, cubeBankLevel(bankSize, slot, lod));
}

// The same in a single atlas of atlasSize texels at level 0.
vec2 cubeAtlasUv(vec3 d, vec2 atlasSize, float lod)
{
    return cubeBankUv(d, atlasSize, vec2(0.0, 1.0), lod);
}
