// Compiling a shader written inside a GL test (a probe around one GLSL include, e.g.
// lafortune.glsl or cube_atlas.glsl): a failure is the test's, with the info log.
#pragma once

#include <string>

#include <GLES3/gl3.h>
#include <gtest/gtest.h>

#include "gles_renderer/gl/gl_object.h"

namespace lumar::test {

inline GlShader compileTestShader(GLenum stage, const std::string& source)
{
    GlShader shader(glCreateShader(stage));
    const char* text = source.c_str();
    glShaderSource(shader.name(), 1, &text, nullptr);
    glCompileShader(shader.name());
    GLint ok = GL_FALSE;
    glGetShaderiv(shader.name(), GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) {
        char log[1024] = {};
        glGetShaderInfoLog(shader.name(), sizeof log, nullptr, log);
        ADD_FAILURE() << log;
    }
    return shader;
}

} // namespace lumar::test
