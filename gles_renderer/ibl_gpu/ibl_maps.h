// The paper's four maps of one environment (DESIGN.md §6.1–6.3): the mirror map (an HDR
// cube map, mipmapped), its nine SH coefficients (projected on the GPU with uniformly
// spaced samples), and the maps derived from them: diffuse (E/pi from the SH), glossy-1 and
// glossy-2 (Phong prefilters at two exponents). Each object owns one set; the real
// environment alone owns another, used by objects whose own maps are not ready.
#pragma once

#include "gles_renderer/gl/gl_object.h"

namespace lumar {

// Sizes and sample counts, chosen by measurement (tests/gl/ibl_maps_test.cpp prints the
// errors against CPU brute force; lumar bench the cost): the glossy lobes at n = 8 and 64
// are wider than a texel of 8 and 16 px faces; 4096 SH samples and 144 lobe samples were
// the smallest counts that kept a sky with a sun within the stated bounds (64 lobe samples:
// 14 % worst texel instead of 8 %).
struct IblSettings {
    int mirrorSize = 64;        // px per face of the environment map
    int shSamples = 4096;       // N uniformly spaced (spherical Fibonacci) directions
    int shRows = 64;            // partial sums in pass 1 (N / rows samples per fragment)
    int diffuseSize = 16;       // px per face of the diffuse map (8 px: bilinear errors ~0.5 %)
    int glossy1Size = 8;        // ... of the glossy map at exponent glossy1Exponent
    int glossy2Size = 16;       // ... at glossy2Exponent
    int prefilterSamples = 144; // lobe samples per glossy-2 texel (from the mirror map)
    int cascadeSamples = 36;    // lobe samples per glossy-1 texel (from glossy-2, already smooth)
    // Store the maps as RGBA8 RGBM even where float targets exist (tests of the fallback).
    bool forceRgbm = false;
    // Render float targets as RGBA16F only, even where RGBA32F is advertised (the board
    // quirk half-float-only: stacks whose RGBA32F render targets are broken or slow).
    bool halfFloatOnly = false;
    float glossy1Exponent = 8.0f;
    float glossy2Exponent = 64.0f;
};

struct IblMaps {
    // RGBA16F cubes; RGBA8 RGBM ones (shaders_es/rgbm.glsl) where the GLES implementation
    // cannot render to a float format.
    GlTexture mirror;       // RGBA16F cube, mipmapped
    GlTexture coefficients; // RGBA32F (or 16F) 1 x 9: the SH9 of the mirror map (rgb)
    GlTexture diffuse;      // RGBA16F cubes
    GlTexture glossy1;
    GlTexture glossy2;
    int mirrorLevels = 1;
    bool ready = false; // rendered at least once
};

} // namespace lumar
