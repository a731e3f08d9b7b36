// Every embedded shader compiles on the real driver and every program links.
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include "core/error.h"
#include "embedded_shaders.h"
#include "gles_renderer/gl/egl_context.h"
#include "gles_renderer/gl/shader_program.h"

namespace lumar {
namespace {

class Shaders : public ::testing::Test {
protected:
    void SetUp() override
    {
        try {
            context_.emplace(EglDisplay::surfaceless());
        } catch (const RuntimeError& e) {
            GTEST_SKIP() << e.what();
        }
    }
    std::optional<EglContext> context_;
};

TEST_F(Shaders, EveryEmbeddedShaderCompiles)
{
    ASSERT_GE(shaders::all().size(), 4u);
    for (const shaders::Entry& entry : shaders::all()) {
        SCOPED_TRACE(std::string(entry.name));
        // .glsl pieces are not stages: they are compiled inside the stages that include them.
        if (entry.name.ends_with(".glsl"))
            continue;
        EXPECT_NO_THROW(compileShader(entry.name));
    }
}

TEST_F(Shaders, EveryProgramTheRendererUsesLinks)
{
    for (const ProgramSources& program : kAllPrograms) {
        SCOPED_TRACE(std::string(program.vertex) + " + " + std::string(program.fragment));
        GlProgram linked;
        EXPECT_NO_THROW(linked = linkProgram(program));
        EXPECT_TRUE(linked);
    }
}

TEST_F(Shaders, MissingShaderIsARuntimeErrorNamingIt)
{
    try {
        compileShader("no_such_shader.frag");
        FAIL() << "expected RuntimeError";
    } catch (const RuntimeError& e) {
        EXPECT_NE(std::string(e.what()).find("no_such_shader.frag"), std::string::npos) << e.what();
    }
    EXPECT_THROW(linkProgram({"fullscreen.vert", "missing.frag"}), RuntimeError);
}

TEST_F(Shaders, ProgramWithoutARequestedUniformIsARuntimeError)
{
    const GlProgram program = linkProgram(kBackgroundProgram);
    EXPECT_THROW(uniformLocation(program, "uNoSuchUniform"), RuntimeError);
    EXPECT_THROW(bindUniformBlock(program, "NoSuchBlock", 0), RuntimeError);
}

} // namespace
} // namespace lumar
