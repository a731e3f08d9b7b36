// lumar: photorealistic AR for embedded Linux (lumar_command_line.h).
#include "gles_renderer/gl/software_rasteriser_threads.h"
#include "lumar_command_line.h"

int main(int argc, char** argv)
{
    // Before any thread or EGL display exists (a software rasteriser's threads start with it).
    (void)lumar::chooseSoftwareRasteriserThreads();
    return lumar::lumarMain({argv + 1, argv + argc});
}
