// How the frame turns the virtual objects' radiance into display values: the response the
// camera image is assumed to have (sRGB-encoded linear light, DESIGN.md §6.5), so a virtual
// surface that reflects a real one (a phantom carrying the camera image, linearised from
// sRGB) shows the real pixel's code value again, and a white virtual card under the light
// that makes the real one code 200 is code 200 too. A filmic curve (ACES) would brighten
// mid-tones by half and set every virtual object apart from the real scene. Above the knee
// an exponential shoulder, tangent at the knee, rolls HDR highlights off towards 1 instead
// of clipping them flat (the camera image itself clips; bloom handles what lies beyond).
const float kResponseKnee = 0.8;

vec3 cameraResponse(vec3 x)
{
    vec3 shoulder = kResponseKnee + (1.0 - kResponseKnee) * (1.0 - exp(-(x - kResponseKnee) / (1.0 - kResponseKnee)));
    return mix(max(x, vec3(0.0)), shoulder, step(vec3(kResponseKnee), x));
}
