// The surfaceless EGL platform gives an OpenGL ES 3 context with no surface.
#include <cstring>
#include <optional>
#include <string>

#include <GLES3/gl3.h>
#include <gtest/gtest.h>

#include "core/error.h"
#include "gles_renderer/gl/egl_context.h"

namespace lumar {
namespace {

std::string glVersion()
{
    const auto* text = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    return text ? text : "";
}

TEST(EglContext, CreatesAnOpenGlEs3ContextWithoutASurface)
{
    std::optional<EglContext> context;
    try {
        context.emplace(EglDisplay::surfaceless());
    } catch (const RuntimeError& e) {
        GTEST_SKIP() << e.what();
    }
    EXPECT_EQ(eglGetCurrentContext(), context->handle());
    EXPECT_EQ(glVersion().rfind("OpenGL ES 3", 0), 0u) << glVersion();
    GLint major = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    EXPECT_GE(major, 3);
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

// eglTerminate does not count references: one context going must not break another.
TEST(EglContext, ContextsShareOneDisplayThatOutlivesEachOfThem)
{
    std::shared_ptr<EglDisplay> display;
    try {
        display = EglDisplay::surfaceless();
    } catch (const RuntimeError& e) {
        GTEST_SKIP() << e.what();
    }
    EXPECT_EQ(EglDisplay::surfaceless(), display);
    std::optional<EglContext> first(std::in_place, display);
    EglContext second(display);
    display.reset();
    first.reset();
    second.makeCurrent();
    EXPECT_EQ(eglGetCurrentContext(), second.handle());
    EXPECT_EQ(glVersion().rfind("OpenGL ES 3", 0), 0u) << glVersion();
}

TEST(EglContext, MovedContextKeepsOwnership)
{
    std::optional<EglContext> context;
    try {
        context.emplace(EglDisplay::surfaceless());
    } catch (const RuntimeError& e) {
        GTEST_SKIP() << e.what();
    }
    const EGLContext handle = context->handle();
    EglContext moved(std::move(*context));
    context.reset(); // the moved-from shell must not destroy the context
    EXPECT_EQ(moved.handle(), handle);
    moved.makeCurrent();
    EXPECT_FALSE(glVersion().empty());
}

} // namespace
} // namespace lumar
