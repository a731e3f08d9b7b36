// The one triangle that covers the viewport, for passes drawn with shaders_es/fullscreen.vert
// (its corners come from gl_VertexID, so it has no vertex attributes).
#pragma once

namespace lumar {

// Draws it with the bound program, under the current viewport and scissor. GLES 3's default
// vertex array (name 0) serves: no empty vertex array object is needed.
void drawFullscreenTriangle();

} // namespace lumar
