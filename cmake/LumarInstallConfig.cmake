# Run by `cmake --install` and cpack (install(SCRIPT) in LumarInstall.cmake): writes the
# installed /etc/lumar/lumar.toml for the prefix being installed to, and installs it.
#   LUMAR_CONFIG_TEMPLATE   the example with @LUMAR_DATA_DIR@ for the asset directory
#   LUMAR_CONFIG_OUT_DIR    where to write the file, in a folder per prefix (`cmake --install`
#                           and cpack may run at once for different prefixes)
#   LUMAR_INSTALL_DATADIR, LUMAR_INSTALL_SYSCONFDIR   GNUInstallDirs' (relative) values
# The configuration directory follows GNUInstallDirs' rule, applied here to the prefix of this
# installation rather than the one configured: /usr -> /etc, /opt/X -> /etc/opt/X, otherwise
# PREFIX/etc (an absolute CMAKE_INSTALL_SYSCONFDIR is used as it is).
if(IS_ABSOLUTE "${LUMAR_INSTALL_SYSCONFDIR}")
  set(lumar_etc "${LUMAR_INSTALL_SYSCONFDIR}")
elseif(CMAKE_INSTALL_PREFIX STREQUAL "/usr" OR CMAKE_INSTALL_PREFIX STREQUAL "/usr/")
  set(lumar_etc "/${LUMAR_INSTALL_SYSCONFDIR}")
elseif(CMAKE_INSTALL_PREFIX MATCHES "^/opt/(.*)")
  set(lumar_etc "/${LUMAR_INSTALL_SYSCONFDIR}/opt/${CMAKE_MATCH_1}")
else()
  set(lumar_etc "${CMAKE_INSTALL_PREFIX}/${LUMAR_INSTALL_SYSCONFDIR}")
endif()

set(LUMAR_DATA_DIR "${CMAKE_INSTALL_PREFIX}/${LUMAR_INSTALL_DATADIR}/lumar")
string(MD5 lumar_prefix_hash "${CMAKE_INSTALL_PREFIX}")
set(lumar_config "${LUMAR_CONFIG_OUT_DIR}/${lumar_prefix_hash}/lumar.toml")
configure_file("${LUMAR_CONFIG_TEMPLATE}" "${lumar_config}" @ONLY)
# file(INSTALL) puts DESTDIR in front of the absolute destination and records the file in
# install_manifest.txt, like install(FILES) would.
file(INSTALL "${lumar_config}" DESTINATION "${lumar_etc}/lumar")
