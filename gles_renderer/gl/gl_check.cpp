#include "gles_renderer/gl/gl_check.h"

#include <cstring>
#include <string>

#include "core/error.h"
#include "gles_renderer/gl/gl_object.h"

namespace lumar {
namespace {

std::string glErrorName(GLenum error)
{
    switch (error) {
    case GL_INVALID_ENUM:
        return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE:
        return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION:
        return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION:
        return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY:
        return "GL_OUT_OF_MEMORY";
    default:
        return "GL error " + std::to_string(error);
    }
}

} // namespace

void throwNoGlName(const char* what)
{
    throw RuntimeError(std::string(what) + " returned no object name");
}

void checkGlError(const char* what)
{
    const GLenum error = glGetError();
    if (error == GL_NO_ERROR)
        return;
    // Drain the remaining flags so the next check reports only its own step.
    while (glGetError() != GL_NO_ERROR) {
    }
    throw RuntimeError(glErrorName(error) + " after " + what);
}

void checkFramebufferComplete(const char* what)
{
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status == GL_FRAMEBUFFER_COMPLETE)
        return;
    std::string name;
    switch (status) {
    case GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT:
        name = "GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT";
        break;
    case GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT:
        name = "GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT";
        break;
    case GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE:
        name = "GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE";
        break;
    case GL_FRAMEBUFFER_UNSUPPORTED:
        name = "GL_FRAMEBUFFER_UNSUPPORTED";
        break;
    default:
        name = "status " + std::to_string(status);
        break;
    }
    throw RuntimeError(std::string(what) + ": framebuffer incomplete (" + name + ")");
}

bool hasGlExtension(const char* name)
{
    GLint count = 0;
    glGetIntegerv(GL_NUM_EXTENSIONS, &count);
    for (GLint i = 0; i < count; ++i) {
        const auto* extension = reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, GLuint(i)));
        if (extension && std::strcmp(extension, name) == 0)
            return true;
    }
    return false;
}

} // namespace lumar
