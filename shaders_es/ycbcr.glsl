// YCbCr code values (0..255) to sRGB code values, with the constants of the CPU converter
// (daemon/capture/v4l2/ycbcr_to_rgb.cpp): Kr, Kb of ITU-R BT.601-7 / BT.709-6, limited range
// expanding Y from [16, 235] and Cb, Cr from [16, 240]. The result is not clamped or rounded:
// the RGBA8 target does both, as the CPU code's fixedToByte does.
vec3 ycbcrToRgb(float y, float cb, float cr, bool bt709, bool fullRange)
{
    float kr = bt709 ? 0.2126 : 0.299;
    float kb = bt709 ? 0.0722 : 0.114;
    float kg = 1.0 - kr - kb;
    float yFull = fullRange ? y : (y - 16.0) * (255.0 / 219.0);
    float cScale = fullRange ? 1.0 : 255.0 / 224.0;
    float u = (cb - 128.0) * cScale;
    float v = (cr - 128.0) * cScale;
    return vec3(yFull + 2.0 * (1.0 - kr) * v,
                yFull - 2.0 * (1.0 - kb) * kb / kg * u - 2.0 * (1.0 - kr) * kr / kg * v,
                yFull + 2.0 * (1.0 - kb) * u);
}
