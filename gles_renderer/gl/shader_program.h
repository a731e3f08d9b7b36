// Shader programs built from the sources embedded from shaders_es/ (looked up by file name).
#pragma once

#include <array>
#include <string_view>

#include "gles_renderer/gl/gl_object.h"

namespace lumar {

// The vertex and fragment shader file names of one program.
struct ProgramSources {
    std::string_view vertex;
    std::string_view fragment;
};

// Every program the renderer links, so a test can check them all.
inline constexpr ProgramSources kBackgroundProgram{"fullscreen.vert", "background.frag"};
inline constexpr ProgramSources kBackgroundYcbcrProgram{"fullscreen.vert", "background_ycbcr.frag"};
inline constexpr ProgramSources kMeshProgram{"mesh.vert", "mesh.frag"};
inline constexpr ProgramSources kDepthOnlyProgram{"depth_only.vert", "depth_only.frag"};
inline constexpr ProgramSources kPhantomProgram{"phantom.vert", "phantom.frag"};
inline constexpr ProgramSources kSkyboxProgram{"cube_face.vert", "skybox.frag"};
inline constexpr ProgramSources kShProjectProgram{"fullscreen.vert", "sh_project_cube.frag"};
inline constexpr ProgramSources kShProjectEquirectProgram{"fullscreen.vert", "sh_project_equirect.frag"};
inline constexpr ProgramSources kShReduceProgram{"fullscreen.vert", "sh_reduce.frag"};
inline constexpr ProgramSources kDiffuseFromShProgram{"cube_face.vert", "diffuse_from_sh.frag"};
inline constexpr ProgramSources kPhongPrefilterProgram{"cube_face.vert", "phong_prefilter.frag"};
inline constexpr ProgramSources kAtlasCopyProgram{"fullscreen.vert", "atlas_copy.frag"};
inline constexpr ProgramSources kPhantomReceiverProgram{"phantom_receiver.vert", "phantom_receiver.frag"};
inline constexpr ProgramSources kPhantomReceiverDepthProgram{"phantom_receiver.vert", "depth_only.frag"};
inline constexpr ProgramSources kPhantomReceiverDistanceProgram{"phantom_receiver.vert",
                                                                "phantom_receiver_distance.frag"};
inline constexpr ProgramSources kShadowApplyProgram{"phantom_receiver.vert", "shadow_apply.frag"};
inline constexpr ProgramSources kShadowDitherStencilProgram{"fullscreen.vert", "shadow_dither_stencil.frag"};
inline constexpr std::array<ProgramSources, 17> kAllPrograms{
    kDepthOnlyProgram,     kBackgroundProgram,     kBackgroundYcbcrProgram,         kMeshProgram,
    kSkyboxProgram,        kShProjectProgram,      kShProjectEquirectProgram,       kShReduceProgram,
    kDiffuseFromShProgram, kPhongPrefilterProgram, kPhantomReceiverProgram,         kPhantomReceiverDepthProgram,
    kPhantomProgram,       kShadowApplyProgram,    kPhantomReceiverDistanceProgram, kShadowDitherStencilProgram,
    kAtlasCopyProgram};
// The environment built from the camera (linked by every renderer that builds one).
inline constexpr ProgramSources kCameraEnvironmentAccumulateProgram{"fullscreen.vert",
                                                                    "camera_environment_accumulate.frag"};
inline constexpr ProgramSources kCameraEnvironmentSkyboxProgram{"cube_face.vert", "camera_environment_skybox.frag"};

// Compiles embedded shader `name`; the stage follows the extension (.vert, .frag).
// Throws RuntimeError "shader NAME: ..." for an unknown name or extension, or with the
// first line of the info log when it does not compile.
// `defines` (lines of "#define NAME VALUE") go right after the source's #version line.
GlShader compileShader(std::string_view name, std::string_view defines = {});

// Compiles and links both stages. Throws RuntimeError naming the shaders and the first
// line of the link log when linking fails.
// `defines` as for compileShader, in both stages: a variant of the program.
GlProgram linkProgram(const ProgramSources& sources, std::string_view defines = {});

// The location of uniform `name`; throws RuntimeError when the program lacks it (a typo
// or an optimised-away uniform would otherwise fail silently).
GLint uniformLocation(const GlProgram& program, const char* name);

// The location of uniform `name`, or -1 where the program has none (a variant that compiled
// out what reads it).
GLint optionalUniformLocation(const GlProgram& program, const char* name);

// Binds uniform block `blockName` to `binding`; throws RuntimeError when it is missing.
void bindUniformBlock(const GlProgram& program, const char* blockName, GLuint binding);

} // namespace lumar
