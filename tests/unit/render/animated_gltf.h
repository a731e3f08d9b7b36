// A generated animated glTF for the animation tests: a bar two units tall standing on the
// origin in the plane z = 0 (x in [-0.1, 0.1]), skinned to a two-joint chain — the hip at the
// origin holds the lower half, the knee one unit up the upper half — whose animation 0
// ("bend") turns the knee from rest to 90 degrees about +z over one second (LINEAR). The top
// corners (+-0.1, 2, 0) then end at (-1, 1 +- 0.1, 0).
#pragma once

#include <string>

#include "mini_gltf.h"

namespace lumar::test {

inline MiniGltf bendingBar(float secondKeyframeTime = 1.0f)
{
    MiniGltf g;
    // Vertices in rows y = 0, 1, 2; the top row follows the knee.
    const size_t positions = g.add<float>({-0.1f, 0, 0, 0.1f, 0, 0, -0.1f, 1, 0, 0.1f, 1, 0, -0.1f, 2, 0, 0.1f, 2, 0});
    const size_t normals = g.add<float>({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1});
    const size_t indices = g.add<uint16_t>({0, 1, 3, 0, 3, 2, 2, 3, 5, 2, 5, 4});
    const size_t joints = g.add<uint8_t>({0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0});
    const size_t weights = g.add<float>({1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0});
    const size_t inverseBind = g.add<float>({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0,  0, 1, //
                                             1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1});
    const size_t times = g.add<float>({0.0f, secondKeyframeTime});
    const float h = 0.70710678f;
    const size_t rotations = g.add<float>({0, 0, 0, 1, 0, 0, h, h});
    const auto view = [](size_t offset, size_t length) {
        return R"({"buffer":0,"byteOffset":)" + std::to_string(offset) + R"(,"byteLength":)" + std::to_string(length) +
               "}";
    };
    g.bufferViews = view(positions, 72) + "," + view(normals, 72) + "," + view(indices, 24) + "," + view(joints, 24) +
                    "," + view(weights, 96) + "," + view(inverseBind, 128) + "," + view(times, 8) + "," +
                    view(rotations, 32);
    g.accessors = R"({"bufferView":0,"componentType":5126,"count":6,"type":"VEC3","min":[-0.1,0,0],"max":[0.1,2,0]},)"
                  R"({"bufferView":1,"componentType":5126,"count":6,"type":"VEC3"},)"
                  R"({"bufferView":2,"componentType":5123,"count":12,"type":"SCALAR"},)"
                  R"({"bufferView":3,"componentType":5121,"count":6,"type":"VEC4"},)"
                  R"({"bufferView":4,"componentType":5126,"count":6,"type":"VEC4"},)"
                  R"({"bufferView":5,"componentType":5126,"count":2,"type":"MAT4"},)"
                  R"({"bufferView":6,"componentType":5126,"count":2,"type":"SCALAR","min":[0],"max":[1]},)"
                  R"({"bufferView":7,"componentType":5126,"count":2,"type":"VEC4"})";
    g.meshes =
        R"({"primitives":[{"attributes":{"POSITION":0,"NORMAL":1,"JOINTS_0":3,"WEIGHTS_0":4},"indices":2,"material":0}]})";
    g.materials = R"({"doubleSided":true})";
    g.nodes = R"({"name":"hip","children":[1,2]},{"name":"knee","translation":[0,1,0]},{"mesh":0,"skin":0})";
    g.extra = R"(,"skins":[{"joints":[0,1],"inverseBindMatrices":5}])"
              R"(,"animations":[{"name":"bend","samplers":[{"input":6,"output":7,"interpolation":"LINEAR"}],)"
              R"("channels":[{"sampler":0,"target":{"node":1,"path":"rotation"}}]}])";
    return g;
}

} // namespace lumar::test
