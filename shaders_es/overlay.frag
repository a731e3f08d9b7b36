#version 300 es
// The overlay pass: a solid colour (atlas coordinate u < 0) or a glyph's coverage from the font
// atlas, blended over the frame by its alpha.
precision mediump float;

uniform sampler2D font; // R8 coverage

in vec2 vAtlasCoord;
in vec4 vColor;

out vec4 fragColor;

void main()
{
    float coverage = vAtlasCoord.x < 0.0 ? 1.0 : texture(font, vAtlasCoord).r;
    fragColor = vec4(vColor.rgb, vColor.a * coverage);
}
