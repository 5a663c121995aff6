# gale-client: networking, jitter buffer, asset cache, HUD, camera (gale_client library),
# the gale-client executable and the client CPU benchmark.
pkg_check_modules(CLIENT_STB REQUIRED IMPORTED_TARGET stb)
add_library(gale_client STATIC
    ${CMAKE_CURRENT_LIST_DIR}/jitter.c
    ${CMAKE_CURRENT_LIST_DIR}/asset_cache.c
    ${CMAKE_CURRENT_LIST_DIR}/hud.c
    ${CMAKE_CURRENT_LIST_DIR}/camera.c)
target_include_directories(gale_client PUBLIC ${CMAKE_CURRENT_LIST_DIR})
target_link_libraries(gale_client PUBLIC gale_protocol PkgConfig::EPOXY PkgConfig::CLIENT_STB ${MATH_LIB})
