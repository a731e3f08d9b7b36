#version 300 es
// The diffuse map: E(n) / pi from nine SH coefficients (Ramamoorthi & Hanrahan 2001, band
// factors pi, 2pi/3, pi/4), one cube face per draw. This is also the normalised Phong
// prefilter of exponent 1, so glossiness blends it with the glossy maps.
precision highp float;
precision highp sampler2D;

uniform mat3 uEnvironmentFromFace;
uniform sampler2D uCoefficients; // slots x 9, RGBA32F
uniform int uSlot;               // the column read
uniform bool uRgbm;              // the face is RGBA8 RGBM (no float render targets)

in vec3 vFaceDirection;
out vec4 fragColor;

#include "sh_basis.glsl"
#include "rgbm.glsl"

void main()
{
    vec3 n = normalize(uEnvironmentFromFace * vFaceDirection);
    float y[9];
    shBasis(n, y);
    const float bandOverPi[3] = float[3](1.0, 2.0 / 3.0, 0.25);
    vec3 e = vec3(0.0);
    for (int j = 0; j < 9; ++j)
        e += texelFetch(uCoefficients, ivec2(uSlot, j), 0).rgb * (y[j] * bandOverPi[j == 0 ? 0 : (j < 4 ? 1 : 2)]);
    fragColor = encodeMapTexel(max(e, vec3(0.0)), uRgbm);
}
