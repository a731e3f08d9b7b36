#include "gles_renderer/scene/model_pose_upload.h"

#include "gles_renderer/assets/gltf_rig.h"
#include "gles_renderer/gl/gl_check.h"

namespace lumar {

GpuModelPose::GpuModelPose(const GltfModel& model) : poser(model.rig)
{
    staging.resize(model.primitives.size());
    for (size_t p = 0; p < model.primitives.size() && p < poser.rig().primitives.size(); ++p)
        if (poser.deforms(p))
            staging[p] = model.primitives[p];
}

std::shared_ptr<GpuModelPose> makeGpuModelPose(const GltfModel& model)
{
    if (!model.rig || model.rig->primitives.size() != model.primitives.size())
        return nullptr;
    return std::make_shared<GpuModelPose>(model);
}

void poseGpuModel(GpuModel& model, std::span<const ClipTime> clips)
{
    GpuModelPose& state = *model.pose;
    ModelPoser& poser = state.poser;
    poser.pose(clips);
    const auto update = [&](std::vector<GpuPrimitive>& primitives) {
        for (GpuPrimitive& primitive : primitives)
            primitive.modelFromMesh = glm::dmat4(poser.modelFromMesh(primitive.source));
    };
    update(model.primitives);
    for (GpuModel::ProxyLevel& level : model.proxyLevels)
        update(level.primitives);
    for (GpuModel::ProxyLevel& level : model.frameLevels)
        update(level.primitives);

    // A deforming model's stand-in is the model itself (uploadModel): the same vertices go
    // into both, interleaved once.
    const auto upload = [&](size_t source) {
        for (GpuPrimitive& primitive : model.primitives)
            if (primitive.source == source)
                replaceVertices(primitive, state.interleaved);
        for (GpuModel::ProxyLevel& level : model.proxyLevels)
            for (GpuPrimitive& primitive : level.primitives)
                if (primitive.source == source)
                    replaceVertices(primitive, state.interleaved);
    };
    for (size_t p = 0; p < state.staging.size(); ++p) {
        if (!poser.deforms(p))
            continue;
        GltfPrimitive& staged = state.staging[p];
        staged.positions = poser.positions(p);
        staged.normals = poser.normals(p);
        staged.tangents = poser.tangents(p);
        interleaveVertices(staged, state.interleaved);
        upload(p);
    }
    model.boundsMin = poser.boundsMin();
    model.boundsMax = poser.boundsMax();
    ++model.poseGeneration;
    checkGlError("uploading a posed model");
}

} // namespace lumar
