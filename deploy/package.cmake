# The Debian package (server/SERVER.md "Debian service"): `cpack -G DEB` in the build tree
# (deploy/package.sh) makes one package, gale, with gale-server, gale-relay and gale-load,
# their systemd units, the configuration in /etc/gale/ and a drop-in that restarts
# Debian's nats-server on failure. gale-client stays out: it reads its shaders from the
# source tree. Its sound plays through ALSA (libasound2, client/CLIENT.md "Sound"): the
# package's runtime dependencies list libasound2 so a console that installs it can run a
# client built beside it, and a build with gale-client installed would add it again
# through the shared-library scan.
include(GNUInstallDirs)
set(GALE_DEB ${CMAKE_CURRENT_LIST_DIR}/debian)
install(TARGETS gale-server gale-relay gale-load RUNTIME DESTINATION bin)
install(FILES ${GALE_DEB}/gale-server.service ${GALE_DEB}/gale-relay.service
        DESTINATION /lib/systemd/system)
install(FILES ${GALE_DEB}/nats-server-restart.conf
        DESTINATION /lib/systemd/system/nats-server.service.d RENAME gale-restart.conf)
install(FILES ${GALE_DEB}/gale-server.conf ${GALE_DEB}/gale-relay.conf DESTINATION /etc/gale)
install(FILES ${GALE_DEB}/copyright DESTINATION share/doc/gale)
install(FILES ${CMAKE_CURRENT_LIST_DIR}/../server/SERVER.md
        ${CMAKE_CURRENT_LIST_DIR}/../protocol/PROTOCOL.md DESTINATION share/doc/gale)
# The browser client gale-server serves from its own binary, also as files (SERVER.md
# "Browser client"), for a site that hosts the pages elsewhere.
install(DIRECTORY ${CMAKE_CURRENT_LIST_DIR}/../web/ DESTINATION share/gale/web
        FILES_MATCHING PATTERN "*.html" PATTERN "*.js" PATTERN "*.css")
install(DIRECTORY ${CMAKE_CURRENT_LIST_DIR}/../shaders/ DESTINATION share/gale/shaders)
# Debian wants the changelog compressed, with no timestamp in the gzip header (a native
# package: changelog.gz)
set(GALE_CHANGELOG_GZ ${CMAKE_BINARY_DIR}/changelog.gz)
add_custom_command(OUTPUT ${GALE_CHANGELOG_GZ}
    COMMAND gzip -9nc ${GALE_DEB}/changelog > ${GALE_CHANGELOG_GZ}
    DEPENDS ${GALE_DEB}/changelog)
add_custom_target(gale_changelog ALL DEPENDS ${GALE_CHANGELOG_GZ})
install(FILES ${GALE_CHANGELOG_GZ} DESTINATION share/doc/gale)

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME gale)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_PACKAGE_CONTACT "gale maintainers <maintainers@example.org>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "forests in wind: simulation server, relay edge and load client")
set(CPACK_DEBIAN_PACKAGE_DESCRIPTION "gale-server simulates trees in wind and streams their
state to thin OpenGL clients over WebSocket; gale-relay serves those
streams from NATS on further machines; gale-load measures a server or
relay with many clients. systemd units for the server and the relay,
configuration in /etc/gale.")
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION net)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "libasound2")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS nats-server)
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA
    ${GALE_DEB}/postinst ${GALE_DEB}/prerm ${GALE_DEB}/postrm ${GALE_DEB}/conffiles)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
include(CPack)
