#include "gles_renderer/gl/gl_census.h"

#include <algorithm>

#include <GLES3/gl3.h>

namespace lumar {
namespace {

// The live names of one kind below the next name `fresh` GL would hand out.
int64_t countAlive(GLuint fresh, GLboolean (*isObject)(GLuint))
{
    int64_t alive = 0;
    const GLuint end = std::min<GLuint>(fresh, kMaxGlCensusNames);
    for (GLuint name = 1; name < end; ++name)
        alive += isObject(name) == GL_TRUE ? 1 : 0;
    return alive;
}

// The name glGen* would hand out next (made and deleted again at once).
template <typename Gen, typename Delete> GLuint nextName(Gen gen, Delete del)
{
    GLuint name = 0;
    gen(1, &name);
    if (name != 0)
        del(1, &name);
    return name;
}

} // namespace

std::vector<std::pair<std::string, int64_t>> glObjectCensus()
{
    // Programs and shaders share one name space.
    const GLuint shader = glCreateShader(GL_VERTEX_SHADER);
    if (shader != 0)
        glDeleteShader(shader);
    return {
        {"textures", countAlive(nextName(glGenTextures, glDeleteTextures), glIsTexture)},
        {"buffers", countAlive(nextName(glGenBuffers, glDeleteBuffers), glIsBuffer)},
        {"vertex_arrays", countAlive(nextName(glGenVertexArrays, glDeleteVertexArrays), glIsVertexArray)},
        {"framebuffers", countAlive(nextName(glGenFramebuffers, glDeleteFramebuffers), glIsFramebuffer)},
        {"renderbuffers", countAlive(nextName(glGenRenderbuffers, glDeleteRenderbuffers), glIsRenderbuffer)},
        {"samplers", countAlive(nextName(glGenSamplers, glDeleteSamplers), glIsSampler)},
        {"programs", countAlive(shader, glIsProgram)},
        {"shaders", countAlive(shader, glIsShader)},
    };
}

} // namespace lumar
