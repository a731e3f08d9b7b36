# Install layout (`cmake --install`; configure with -DCMAKE_INSTALL_PREFIX=/usr for a system
# installation, which puts the configuration in /etc/lumar):
#   bin/lumar, share/lumar/{models,env,calibration,scenes}, /etc/lumar/lumar.toml (the documented
#   example with absolute asset paths), lib/systemd/system/lumar.service.
include(GNUInstallDirs)

install(TARGETS lumar RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY "${PROJECT_SOURCE_DIR}/daemon/assets/models" "${PROJECT_SOURCE_DIR}/daemon/assets/env"
                  "${PROJECT_SOURCE_DIR}/daemon/assets/calibration" "${PROJECT_SOURCE_DIR}/daemon/assets/scenes"
        DESTINATION ${CMAKE_INSTALL_DATADIR}/lumar)
install(FILES "${PROJECT_SOURCE_DIR}/daemon/assets/README.md" DESTINATION ${CMAKE_INSTALL_DATADIR}/lumar)

# The shipped example names its assets relative to itself; installed in /etc it names them
# where they are installed.
file(READ "${PROJECT_SOURCE_DIR}/daemon/assets/lumar.toml" lumar_toml)
set(lumar_data "${CMAKE_INSTALL_FULL_DATADIR}/lumar")
foreach(folder models env calibration)
  string(REPLACE "\"${folder}/" "\"${lumar_data}/${folder}/" lumar_toml "${lumar_toml}")
endforeach()
file(WRITE "${PROJECT_BINARY_DIR}/installed/lumar.toml" "${lumar_toml}")
install(FILES "${PROJECT_BINARY_DIR}/installed/lumar.toml" DESTINATION ${CMAKE_INSTALL_FULL_SYSCONFDIR}/lumar)
install(FILES "${PROJECT_SOURCE_DIR}/systemd/lumar.service" DESTINATION lib/systemd/system)

