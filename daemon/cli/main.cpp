// lumar: photorealistic AR for embedded Linux (lumar_command_line.h).
#include "lumar_command_line.h"

int main(int argc, char** argv)
{
    return lumar::lumarMain({argv + 1, argv + argc});
}
