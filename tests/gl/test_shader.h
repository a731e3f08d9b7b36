// The set-up of GL tests that probe shaders directly (one GLSL include, e.g. lafortune.glsl or
// cube_atlas.glsl, or one IblPipeline pass) without a renderer: a surfaceless context, or a
// skip where none exists, and shaders compiled with their info log as the test's failure.
#pragma once

#include <optional>
#include <string>

#include <GLES3/gl3.h>
#include <gtest/gtest.h>

#include "core/error.h"
#include "embedded_shaders.h"
#include "gles_renderer/gl/egl_context.h"
#include "gles_renderer/gl/gl_object.h"

// Makes `context` (a std::optional<lumar::EglContext>) current on a surfaceless display, or
// skips the test where no GLES 3 context can be made.
#define LUMAR_CONTEXT_OR_SKIP(context)                                                                                 \
    std::optional<::lumar::EglContext> context;                                                                        \
    try {                                                                                                              \
        context.emplace(::lumar::EglDisplay::surfaceless());                                                           \
    } catch (const ::lumar::RuntimeError& e) {                                                                         \
        GTEST_SKIP() << "no GLES 3 context: " << e.what();                                                             \
    }

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

// A program of fullscreen.vert and `fragment` (a whole shader: #version, precisions, the
// GLSL include under test and a main), linked; compile and link logs become the test's failures.
inline GlProgram linkFullscreenTestProgram(const std::string& fragment)
{
    GlProgram program = GlProgram::create();
    const GlShader vs = compileTestShader(GL_VERTEX_SHADER, std::string(shaders::source("fullscreen.vert")));
    const GlShader fs = compileTestShader(GL_FRAGMENT_SHADER, fragment);
    glAttachShader(program.name(), vs.name());
    glAttachShader(program.name(), fs.name());
    glLinkProgram(program.name());
    GLint linked = GL_FALSE;
    glGetProgramiv(program.name(), GL_LINK_STATUS, &linked);
    if (linked != GL_TRUE) {
        char log[1024] = {};
        glGetProgramInfoLog(program.name(), sizeof log, nullptr, log);
        ADD_FAILURE() << "link: " << log;
    }
    return program;
}

} // namespace lumar::test
