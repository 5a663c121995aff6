# gale-client: networking, jitter buffer, asset cache, HUD, camera (gale_client library),
# the gale-client executable and the client CPU benchmark.
pkg_check_modules(CLIENT_STB REQUIRED IMPORTED_TARGET stb)
add_library(gale_client STATIC
    ${CMAKE_CURRENT_LIST_DIR}/jitter.c
    ${CMAKE_CURRENT_LIST_DIR}/asset_cache.c
    ${CMAKE_CURRENT_LIST_DIR}/hud.c
    ${CMAKE_CURRENT_LIST_DIR}/camera.c
    ${CMAKE_CURRENT_LIST_DIR}/net.c)
target_include_directories(gale_client PUBLIC ${CMAKE_CURRENT_LIST_DIR})
target_link_libraries(gale_client PUBLIC gale_protocol PkgConfig::LWS PkgConfig::EPOXY
    PkgConfig::CLIENT_STB ${MATH_LIB})

# The executable needs the render library (client/render.cmake, included before this).
if(TARGET gale_render)
    add_executable(gale-client ${CMAKE_CURRENT_LIST_DIR}/main.c)
    target_link_libraries(gale-client PRIVATE gale_client gale_render gale_protocol
        PkgConfig::LWS PkgConfig::GLFW PkgConfig::EPOXY ${MATH_LIB})
endif()

# gale-bench client: client CPU per frame (receive, decode, jitter, upload).
set_property(GLOBAL APPEND PROPERTY GALE_BENCH_SOURCES ${CMAKE_CURRENT_LIST_DIR}/bench_client.c)
set_property(GLOBAL APPEND PROPERTY GALE_BENCH_LIBS gale_client gale_protocol PkgConfig::GLFW
    PkgConfig::EPOXY)
