# Install layout (`cmake --install`; configure with -DCMAKE_INSTALL_PREFIX=/usr for a system
# installation, which puts the configuration in /etc/lumar) and the Debian package
# (`cpack -G DEB` in the build directory, always for prefix /usr):
#   bin/lumar, share/lumar/{models,env,calibration,scenes,board}, /etc/lumar/lumar.toml (the
#   documented example with absolute asset paths), lib/systemd/system/lumar.service,
#   lib/tmpfiles.d/lumar.conf.
include(GNUInstallDirs)

install(TARGETS lumar RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY "${PROJECT_SOURCE_DIR}/daemon/assets/models" "${PROJECT_SOURCE_DIR}/daemon/assets/env"
                  "${PROJECT_SOURCE_DIR}/daemon/assets/calibration" "${PROJECT_SOURCE_DIR}/daemon/assets/scenes"
                  "${PROJECT_SOURCE_DIR}/board"
        DESTINATION ${CMAKE_INSTALL_DATADIR}/lumar)
install(FILES "${PROJECT_SOURCE_DIR}/daemon/assets/README.md" DESTINATION ${CMAKE_INSTALL_DATADIR}/lumar)
install(FILES "${PROJECT_SOURCE_DIR}/systemd/lumar.service" DESTINATION lib/systemd/system)
install(FILES "${PROJECT_SOURCE_DIR}/systemd/lumar.tmpfiles" DESTINATION lib/tmpfiles.d RENAME lumar.conf)

# The shipped example names its assets relative to itself; installed in /etc it names them
# where they are installed. Both places depend on the prefix, which cpack changes at install
# time (the package is for /usr whatever this tree was configured with), so the file is
# written and placed by cmake/LumarInstallConfig.cmake when installing, not here.
file(READ "${PROJECT_SOURCE_DIR}/daemon/assets/lumar.toml" lumar_toml)
foreach(folder models env calibration)
  string(REPLACE "\"${folder}/" "\"@LUMAR_DATA_DIR@/${folder}/" lumar_toml "${lumar_toml}")
endforeach()
file(WRITE "${PROJECT_BINARY_DIR}/installed/lumar.toml.in" "${lumar_toml}")
install(CODE "set(LUMAR_CONFIG_TEMPLATE \"${PROJECT_BINARY_DIR}/installed/lumar.toml.in\")
set(LUMAR_CONFIG_OUT_DIR \"${PROJECT_BINARY_DIR}/installed\")
set(LUMAR_INSTALL_DATADIR \"${CMAKE_INSTALL_DATADIR}\")
set(LUMAR_INSTALL_SYSCONFDIR \"${CMAKE_INSTALL_SYSCONFDIR}\")")
install(SCRIPT "${PROJECT_SOURCE_DIR}/cmake/LumarInstallConfig.cmake")

# Debian package. Installing with DESTDIR and prefix /usr (CPACK_SET_DESTDIR) lets the
# configuration land in /etc as GNUInstallDirs places it for /usr; dpkg keeps an
# administrator's edits to it across upgrades because it is listed as a conffile.
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME lumar)
set(CPACK_PACKAGE_VENDOR lumar)
set(CPACK_PACKAGE_CONTACT "lumar maintainers <lumar@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "augmented-reality renderer for camera + display appliances")
set(CPACK_PACKAGE_DESCRIPTION
    "lumar tracks AprilTag markers in a camera's frames and renders glTF objects on them, lit by \
per-object environment maps, with OpenGL ES through EGL/GBM. It runs as a systemd service.")
set(CPACK_SET_DESTDIR ON)
set(CPACK_INSTALL_PREFIX /usr)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION video)
# Depends: from the libraries the binary links, as dpkg-shlibdeps finds them.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# The libraries link libEGL from glvnd, which needs a vendor (Mesa's) and its drivers to do
# anything; dpkg-shlibdeps cannot see that, so they are named here.
set(CPACK_DEBIAN_PACKAGE_DEPENDS "libegl-mesa0, libgl1-mesa-dri")
file(WRITE "${PROJECT_BINARY_DIR}/deb/conffiles" "/etc/lumar/lumar.toml\n")
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA
    "${PROJECT_BINARY_DIR}/deb/conffiles;${PROJECT_SOURCE_DIR}/cmake/deb/postinst;${PROJECT_SOURCE_DIR}/cmake/deb/prerm;${PROJECT_SOURCE_DIR}/cmake/deb/postrm")
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
include(CPack)
