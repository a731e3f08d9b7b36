#version 300 es
// The overlay pass (gles_renderer/overlay/overlay_pass.h): positions in the frame's pixels,
// OpenCV's convention (pixel centres at integer coordinates), row 0 the framebuffer's row 0.
layout(location = 0) in vec2 position;
layout(location = 1) in vec2 atlasCoord;
layout(location = 2) in vec4 color;

uniform vec2 viewSize; // the framebuffer, pixels

out vec2 vAtlasCoord;
out vec4 vColor;

void main()
{
    vAtlasCoord = atlasCoord;
    vColor = color;
    gl_Position = vec4((position + 0.5) / viewSize * 2.0 - 1.0, 0.0, 1.0);
}
