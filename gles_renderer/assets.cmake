# lumar_assets: CPU-side asset loading for the renderer (glTF models with their materials and
# textures, Radiance .hdr environment maps, SH9 projection). No GL: unit tests link it alone.
add_library(lumar_assets STATIC
  "${CMAKE_CURRENT_LIST_DIR}/builtin_shapes.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/cube_map.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/environment_map.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/gltf_accessors.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/gltf_materials.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/gltf_model.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/gltf_parse.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/lafortune_material.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/lafortune_shading.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/material_sidecar.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/mesh_simplify.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/radiance_hdr_check.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/rgba8_conversion.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/sh_projection.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/sphere_samples.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/tangent_space.cpp")
target_link_libraries(lumar_assets
  PUBLIC lumar_core
  PRIVATE TinyGLTF::TinyGLTF PkgConfig::STB meshoptimizer::meshoptimizer tomlplusplus::tomlplusplus lumar_build_flags)
