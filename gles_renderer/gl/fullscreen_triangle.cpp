#include "gles_renderer/gl/fullscreen_triangle.h"

#include <GLES3/gl3.h>

namespace lumar {

void drawFullscreenTriangle()
{
    glBindVertexArray(0);
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

} // namespace lumar
