// lumar check-config FILE: exit 0 when the file is a valid configuration or board profile
// (told apart by a top-level [board] table), else exit 2 with one line "FILE:LINE: what is
// wrong" on stderr.
#include <cstdio>
#include <string>

#include "commands.h"
#include "config/board_profile.h"
#include "config/config.h"
#include "core/error.h"
#include "gles_renderer/assets/builtin_shapes.h"
#include "gles_renderer/assets/gltf_model.h"
#include "object_animation.h"

namespace lumar {
namespace {

// An object's animation named or numbered ([[objects]] animation = "Walk" | 2) is checked
// against its model here as the daemon's load checks it before applying a (re)load; the
// model is read only for such objects ("all", "none" and the default need no model).
void checkObjectAnimations(const Config& config, const std::string& file)
{
    for (size_t i = 0; i < config.objects.size(); ++i) {
        const ObjectConfig& object = config.objects[i];
        const bool named = object.animationIndex >= 0 ||
                           (!object.animation.empty() && object.animation != "all" && object.animation != "none");
        if (!named || object.model.string().starts_with(kBuiltinModelPrefix))
            continue;
        try {
            (void)resolveObjectAnimation(object, loadGltfModel(object.model));
        } catch (const InputError& e) {
            throw InputError(file + ":" + std::to_string(object.animationLine) + ": objects[" + std::to_string(i) +
                             "].animation: " + e.what());
        }
    }
}

} // namespace

int checkConfigCommand(const CheckConfigCommandOptions& options)
{
    const std::string& file = options.file;
    try {
        if (isBoardProfileFile(file))
            (void)loadBoardProfile(file);
        else
            checkObjectAnimations(loadConfig(file), file);
    } catch (const InputError& e) {
        // Exactly one line, FILE:LINE: message, so editors and scripts can jump to it.
        std::fprintf(stderr, "%s\n", e.what());
        return kExitBadInput;
    }
    std::printf("%s: ok\n", file.c_str());
    return kExitOk;
}

} // namespace lumar
