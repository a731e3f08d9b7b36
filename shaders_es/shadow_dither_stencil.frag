#version 300 es
// Writes the shadow map's stencil with the 4 x 4 Bayer matrix of depth_only.frag (drawn once
// per threshold, uLevel, with the stencil set to replace): casters of one opacity (glass)
// then keep round(16 x opacity) texels of each 4 x 4 block through the stencil test alone,
// with the plain depth program, so nothing is discarded and llvmpipe's early depth stays on.
precision mediump float;

uniform int uLevel;

// The 4 x 4 Bayer matrix (by rows 0 8 2 10, 12 4 14 6, 3 11 1 9, 15 7 13 5; depth_only.frag's
// kBayer): the bits of x ^ y and y interleaved, lowest first.
int bayer(ivec2 cell)
{
    int a = cell.x ^ cell.y;
    return ((a & 1) << 3) | ((cell.y & 1) << 2) | (a & 2) | ((cell.y & 2) >> 1);
}

void main()
{
    if (bayer(ivec2(gl_FragCoord.xy) & 3) != uLevel)
        discard;
}
