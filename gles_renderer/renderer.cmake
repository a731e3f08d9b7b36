# lumar_render: the GLES 3 pipeline on a surfaceless or GBM EGL context (EGL setup, GL RAII wrappers,
# shader programs, the background and mesh passes, the scene renderer behind scene_renderer.h)
# and the DRM/KMS display sink.
add_library(lumar_render STATIC
  "${CMAKE_CURRENT_LIST_DIR}/background_pass.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/camera_projection.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/cube_face_camera.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/dmabuf_image.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/drm_device.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/drm_probe.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/egl_context.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/environment_lighting.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/environment_probes.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/frame_readback.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/gbm_surface.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/gl_check.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/gl_probe.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/gles_scene_renderer.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/gpu_model.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/gpu_texture.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/ibl_pipeline.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/kms_display.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/kms_output.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/mesh_pass.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/render_target.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/shader_program.cpp")
target_link_libraries(lumar_render
  PUBLIC lumar_core lumar_assets PkgConfig::LIBDRM PkgConfig::GBM
  PRIVATE lumar_shaders PkgConfig::EGL PkgConfig::GLESV2 lumar_build_flags)
