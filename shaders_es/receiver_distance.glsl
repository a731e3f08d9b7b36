// The receivers' distance from the camera as ShadowPass's darkening buffer stores it beside the
// ratio (two 8-bit channels): 4096 codes per octave of log2(distance) from 2^-8 m (4 mm) to
// 2^8 m, a step of 0.017 % of the distance at any scale. Code 65535 (the buffer's clear
// value) is "no receiver here". The apply pass (shadow_apply.frag) compares a frame pixel's
// own distance with its neighbouring texels' to take the darkening only from its own surface.

const float kDistanceCodesPerOctave = 4096.0;
const float kDistanceLowOctave = -8.0;
const float kNoReceiverCode = 65535.0;

// The code of a distance (metres), unrounded.
float distanceCode(vec3 position)
{
    return (log2(max(length(position), 1e-6)) - kDistanceLowOctave) * kDistanceCodesPerOctave;
}

// Two channels (high byte, low byte) of a distance's code, for an RGBA8 target.
vec2 encodeDistance(vec3 position)
{
    float code = clamp(floor(distanceCode(position) + 0.5), 0.0, kNoReceiverCode - 1.0);
    float high = floor(code / 256.0);
    return vec2(high, code - 256.0 * high) / 255.0;
}

float decodeDistance(vec2 channels)
{
    return dot(floor(channels * 255.0 + 0.5), vec2(256.0, 1.0));
}
