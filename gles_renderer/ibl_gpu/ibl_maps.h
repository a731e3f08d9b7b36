// The paper's four maps of one environment (DESIGN.md §6.1–6.3): the mirror map (an HDR
// cube map, mipmapped), its nine SH coefficients (projected on the GPU with uniformly
// spaced samples), and the maps derived from them: diffuse (E/pi from the SH), glossy-1 and
// glossy-2 (Phong prefilters at two exponents). Each object owns one set; the real
// environment alone owns another, used by objects whose own maps are not ready.
#pragma once

#include <glm/glm.hpp>

#include "gles_renderer/gl/gl_object.h"

namespace lumar {

// Sizes and sample counts, chosen by measurement (tests/gl/ibl_maps_test.cpp prints the
// errors against CPU brute force; lumar bench the cost): the glossy lobes at n = 8 and 64
// are wider than a texel of 8 and 16 px faces; 4096 SH samples were the smallest count that
// kept a sky with a sun within the stated bounds. Where mesh.frag reads them, between texel
// centres (tests/gl/ibl_lookup_test.cpp), most of glossy-2's error is its face size's: next
// to venice's sun 0.096 of the peak for exact 16-px texels, 0.198 at 8 px. glossy-2's lobe
// samples, importance-sampled with a mip level each (IblPipeline::makeLobePrefilter): 112
// give 0.081 worst, 0.0110 rms there (104: 0.091, 0.0124; 100: 0.100, 0.0146; 96: 0.122,
// 0.0152, out of bounds); the former equal-solid-angle samples from one level needed 144
// (0.116, 0.0125). 112, not 104: margin, and at 104 a glossy-1 texel of ibl_bank_test's
// RGBM bank rounds one code apart from the same map built alone (bank and single-atlas
// coordinates round differently; 88-144 samples: none but 104 and 144 show it).
struct IblSettings {
    int mirrorSize = 64;        // px per face of the environment map
    int shSamples = 4096;       // N uniformly spaced (spherical Fibonacci) directions
    int shRows = 64;            // partial sums in pass 1 (N / rows samples per fragment)
    int diffuseSize = 16;       // px per face of the diffuse map (8 px: bilinear errors ~0.5 %)
    int glossy1Size = 8;        // ... of the glossy map at exponent glossy1Exponent
    int glossy2Size = 16;       // ... at glossy2Exponent
    int prefilterSamples = 112; // lobe samples per glossy-2 texel (from the mirror's levels)
    int cascadeSamples = 36;    // lobe samples per glossy-1 texel (from glossy-2, already smooth)
    // Store the maps as RGBA8 RGBM even where float targets exist (tests of the fallback).
    bool forceRgbm = false;
    // Render float targets as RGBA16F only, even where RGBA32F is advertised (the board
    // quirk half-float-only: stacks whose RGBA32F render targets are broken or slow).
    bool halfFloatOnly = false;
    float glossy1Exponent = 8.0f;
    float glossy2Exponent = 64.0f;
};

// The cube maps are 2D atlases (shaders_es/cube_atlas.glsl samples them): face f of a map
// with faces of `size` px is the size x size square at cubeAtlasCellOrigin(f, size) of a
// kAtlasColumns x kAtlasRows grid of cells, its rows in GL cube-face order (row 0 at t = 0).
// A cube texture would need a copy of each face out of the framebuffer it is rendered in,
// and llvmpipe drains its rasteriser threads before every copy. (3 x 2 rather than a 6 x 1
// row: within GLES 3.0's minimum texture size, 2048 px, up to 512-px faces.)
constexpr int kAtlasColumns = 3;
constexpr int kAtlasRows = 2;
// llvmpipe bins a framebuffer in tiles of 64 px and shares whole tiles between its threads:
// cells at least a tile wide put the faces of a small map in three tiles, not one, so both
// threads draw them (16-px glossy faces in one tile took twice the time).
constexpr int kAtlasMinCellWidth = 64;

inline int cubeAtlasCellWidth(int size)
{
    return size > kAtlasMinCellWidth ? size : kAtlasMinCellWidth;
}

// Level 0's size of the atlas of a map with `size`-px faces.
inline glm::ivec2 cubeAtlasSize(int size)
{
    return {kAtlasColumns * cubeAtlasCellWidth(size), kAtlasRows * size};
}

// Where face `face` starts at level 0 (at level L: shifted right by L).
inline glm::ivec2 cubeAtlasCellOrigin(int face, int size)
{
    return {face % kAtlasColumns * cubeAtlasCellWidth(size), face / kAtlasColumns * size};
}

// A map bank: the textures of a set hold `slots` atlases of each kind stacked bottom to top
// (slot k's rows from k x the atlas's height), so the maps of several objects are drawn in
// one pass per kind (IblPipeline's *Slots functions): llvmpipe pays for every framebuffer it
// renders (a flush, and a wait where the next pass reads it), which for the objects' small
// maps cost more than their texels. Atlas heights are multiples of the mirror map's last
// level's 2 x 2 boxes (the faces are powers of two), so mip levels keep the slots apart.
// The textures of a set's maps as shaders bind them, and the set's slot among `slots`.
struct IblTextures {
    GLuint mirror = 0;
    GLuint coefficients = 0; // slots x 9: slot k's coefficients in column k
    GLuint diffuse = 0;
    GLuint glossy1 = 0;
    GLuint glossy2 = 0;
    int slot = 0;
    int slots = 1;
};

struct IblMaps {
    // RGBA16F cube atlases; RGBA8 RGBM ones (shaders_es/rgbm.glsl) where the GLES
    // implementation cannot render to a float format. Empty in a view of a bank's slot.
    GlTexture mirror;       // RGBA16F cube atlas, mipmapped (2 x 2 boxes stay inside their cells)
    GlTexture coefficients; // RGBA32F (or 16F) slots x 9: the SH9 of the mirror map (rgb)
    GlTexture diffuse;      // RGBA16F cube atlases, one level
    GlTexture glossy1;
    GlTexture glossy2;
    int mirrorLevels = 1;
    int slots = 1; // atlases stacked in each texture (a bank)
    // A view of one slot of a bank (EnvironmentProbes): the bank's textures, which change
    // from frame to frame (its mirror maps are drawn into two textures in turn).
    IblTextures view;
    bool ready = false; // rendered at least once

    [[nodiscard]] IblTextures textures() const
    {
        if (view.mirror != 0)
            return view;
        return {mirror.name(), coefficients.name(), diffuse.name(), glossy1.name(), glossy2.name(), 0, slots};
    }
};

} // namespace lumar
