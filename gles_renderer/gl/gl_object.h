// Move-only owners of GL object names: the name is deleted when the owner goes, so no
// logic code ever calls glDelete*. They must be destroyed while their context is current.
#pragma once

#include <utility>

#include <GLES3/gl3.h>

namespace lumar {

template <typename Traits> class GlObject {
public:
    GlObject() = default;
    // Takes ownership of an existing name (0 = none).
    explicit GlObject(GLuint name) : name_(name) {}
    GlObject(GlObject&& other) noexcept : name_(std::exchange(other.name_, 0)) {}
    GlObject& operator=(GlObject&& other) noexcept
    {
        if (this != &other) {
            reset();
            name_ = std::exchange(other.name_, 0);
        }
        return *this;
    }
    GlObject(const GlObject&) = delete;
    GlObject& operator=(const GlObject&) = delete;
    ~GlObject() { reset(); }

    // A fresh name from glGen*/glCreate* (throws RuntimeError when GL gives none).
    static GlObject create() { return GlObject(Traits::create()); }

    [[nodiscard]] GLuint name() const { return name_; }
    explicit operator bool() const { return name_ != 0; }
    void reset()
    {
        if (name_ != 0)
            Traits::destroy(name_);
        name_ = 0;
    }

private:
    GLuint name_ = 0;
};

// Throws RuntimeError naming `what` (GL handed out no object name).
[[noreturn]] void throwNoGlName(const char* what);

namespace gl_traits {

// Objects made and deleted by glGen*/glDelete* pairs.
template <auto genFunction, auto deleteFunction> struct Generated {
    static GLuint create()
    {
        GLuint name = 0;
        genFunction(1, &name);
        if (name == 0)
            throwNoGlName("glGen*");
        return name;
    }
    static void destroy(GLuint name) { deleteFunction(1, &name); }
};

struct Program {
    static GLuint create()
    {
        const GLuint name = glCreateProgram();
        if (name == 0)
            throwNoGlName("glCreateProgram");
        return name;
    }
    static void destroy(GLuint name) { glDeleteProgram(name); }
};

// Shaders need a type to be created: construct GlShader from glCreateShader's result.
struct Shader {
    static void destroy(GLuint name) { glDeleteShader(name); }
};

} // namespace gl_traits

using GlBuffer = GlObject<gl_traits::Generated<glGenBuffers, glDeleteBuffers>>;
using GlVertexArray = GlObject<gl_traits::Generated<glGenVertexArrays, glDeleteVertexArrays>>;
using GlTexture = GlObject<gl_traits::Generated<glGenTextures, glDeleteTextures>>;
using GlFramebuffer = GlObject<gl_traits::Generated<glGenFramebuffers, glDeleteFramebuffers>>;
using GlRenderbuffer = GlObject<gl_traits::Generated<glGenRenderbuffers, glDeleteRenderbuffers>>;
using GlSampler = GlObject<gl_traits::Generated<glGenSamplers, glDeleteSamplers>>;
using GlProgram = GlObject<gl_traits::Program>;
using GlShader = GlObject<gl_traits::Shader>;

} // namespace lumar
