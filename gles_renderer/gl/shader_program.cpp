#include "gles_renderer/gl/shader_program.h"

#include <algorithm>
#include <string>

#include "core/error.h"
#include "embedded_shaders.h"

namespace lumar {
namespace {

// The first non-empty line of an info log: enough to name the problem on one line.
std::string firstLine(const std::string& log)
{
    size_t start = 0;
    while (start < log.size()) {
        size_t end = log.find('\n', start);
        if (end == std::string::npos)
            end = log.size();
        if (end > start)
            return log.substr(start, end - start);
        start = end + 1;
    }
    return "(no info log)";
}

std::string shaderLog(GLuint shader)
{
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(size_t(std::max(length, 1)), '\0');
    glGetShaderInfoLog(shader, GLsizei(log.size()), nullptr, log.data());
    return log.c_str();
}

std::string programLog(GLuint program)
{
    GLint length = 0;
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    std::string log(size_t(std::max(length, 1)), '\0');
    glGetProgramInfoLog(program, GLsizei(log.size()), nullptr, log.data());
    return log.c_str();
}

GLenum stageOf(std::string_view name)
{
    if (name.ends_with(".vert"))
        return GL_VERTEX_SHADER;
    if (name.ends_with(".frag"))
        return GL_FRAGMENT_SHADER;
    throw RuntimeError("shader " + std::string(name) + ": unknown stage (expected .vert or .frag)");
}

} // namespace

GlShader compileShader(std::string_view name, std::string_view defines)
{
    const std::string_view text = shaders::source(name);
    if (text.empty())
        throw RuntimeError("shader " + std::string(name) + ": no such embedded shader");
    GlShader shader(glCreateShader(stageOf(name)));
    if (!shader)
        throwNoGlName("glCreateShader");
    // The #version line must come first: the defines follow it.
    const size_t versionEnd = std::min(text.find('\n') + 1, text.size());
    const GLchar* sources[] = {text.data(), defines.empty() ? "" : defines.data(), text.data() + versionEnd};
    const GLint lengths[] = {GLint(versionEnd), GLint(defines.size()), GLint(text.size() - versionEnd)};
    glShaderSource(shader.name(), 3, sources, lengths);
    glCompileShader(shader.name());
    GLint compiled = GL_FALSE;
    glGetShaderiv(shader.name(), GL_COMPILE_STATUS, &compiled);
    if (compiled != GL_TRUE)
        throw RuntimeError("shader " + std::string(name) + " does not compile: " + firstLine(shaderLog(shader.name())));
    return shader;
}

GlProgram linkProgram(const ProgramSources& sources, std::string_view defines)
{
    const GlShader vertex = compileShader(sources.vertex, defines);
    const GlShader fragment = compileShader(sources.fragment, defines);
    GlProgram program = GlProgram::create();
    glAttachShader(program.name(), vertex.name());
    glAttachShader(program.name(), fragment.name());
    glLinkProgram(program.name());
    GLint linked = GL_FALSE;
    glGetProgramiv(program.name(), GL_LINK_STATUS, &linked);
    // The program keeps the compiled code; the shader objects can go with this scope.
    glDetachShader(program.name(), vertex.name());
    glDetachShader(program.name(), fragment.name());
    if (linked != GL_TRUE)
        throw RuntimeError("program " + std::string(sources.vertex) + " + " + std::string(sources.fragment) +
                           " does not link: " + firstLine(programLog(program.name())));
    return program;
}

GLint optionalUniformLocation(const GlProgram& program, const char* name)
{
    return glGetUniformLocation(program.name(), name);
}

GLint uniformLocation(const GlProgram& program, const char* name)
{
    const GLint location = glGetUniformLocation(program.name(), name);
    if (location < 0)
        throw RuntimeError(std::string("shader program has no active uniform ") + name);
    return location;
}

void bindUniformBlock(const GlProgram& program, const char* blockName, GLuint binding)
{
    const GLuint index = glGetUniformBlockIndex(program.name(), blockName);
    if (index == GL_INVALID_INDEX)
        throw RuntimeError(std::string("shader program has no uniform block ") + blockName);
    glUniformBlockBinding(program.name(), index, binding);
}

} // namespace lumar
