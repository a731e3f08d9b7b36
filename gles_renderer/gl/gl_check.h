// Turning GL's sticky error flags into exceptions at the end of each setup step (never per
// draw: glGetError may stall a pipelined driver).
#pragma once

#include <GLES3/gl3.h>

namespace lumar {

// Throws RuntimeError "GL error GL_INVALID_VALUE after <what>" if GL recorded an error.
void checkGlError(const char* what);

// Throws RuntimeError naming `what` and the status when the bound GL_FRAMEBUFFER is incomplete.
void checkFramebufferComplete(const char* what);

// Whether the current context lists GL extension `name` (e.g. "GL_EXT_color_buffer_float").
bool hasGlExtension(const char* name);

} // namespace lumar
