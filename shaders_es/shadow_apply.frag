#version 300 es
// Multiplies the frame (glBlendFunc(GL_DST_COLOR, GL_ZERO)) by the real surfaces' darkening,
// which ShadowPass::drawReceivers shades at a fraction of the frame's resolution
// (phantom_receiver.frag): filtered bilinearly, so the soft shadows and the contact
// darkening stay smooth. A texel of 1 leaves its pixels exactly as the camera saw them.
precision highp float;
precision highp sampler2D;

uniform sampler2D uRatio;
uniform vec2 uRatioFromFragCoord; // 1 / the frame's size in pixels

out vec4 fragColor;

void main()
{
    float ratio = texture(uRatio, gl_FragCoord.xy * uRatioFromFragCoord).r;
    if (ratio >= 1.0)
        discard;
    fragColor = vec4(vec3(ratio), 1.0);
}
