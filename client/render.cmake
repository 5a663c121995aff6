# gale_render: GPU reconstruction, skinning, leaves, falling leaves, LOD (client/render*.c,
# gl_ctx.c, falling_path.c; shaders read at run time from ${CMAKE_SOURCE_DIR}/shaders or
# $GALE_SHADER_DIR). gale-render: renders a scene to a PNG headless.
pkg_check_modules(EGL REQUIRED IMPORTED_TARGET egl)
pkg_check_modules(STB REQUIRED IMPORTED_TARGET stb)
add_library(gale_render STATIC
    ${CMAKE_CURRENT_LIST_DIR}/render.c
    ${CMAKE_CURRENT_LIST_DIR}/render_shader.c
    ${CMAKE_CURRENT_LIST_DIR}/render_demo.c
    ${CMAKE_CURRENT_LIST_DIR}/gl_ctx.c
    ${CMAKE_CURRENT_LIST_DIR}/falling_path.c)
target_include_directories(gale_render PUBLIC ${CMAKE_CURRENT_LIST_DIR})
target_link_libraries(gale_render PUBLIC gale_protocol PkgConfig::GLFW PkgConfig::EPOXY
    PkgConfig::EGL PkgConfig::CGLM PkgConfig::STB ${MATH_LIB})

add_executable(gale-render ${CMAKE_CURRENT_LIST_DIR}/render_tool.c)
target_link_libraries(gale-render PRIVATE gale_render)

set_property(GLOBAL APPEND PROPERTY GALE_BENCH_SOURCES ${CMAKE_CURRENT_LIST_DIR}/bench_render.c)
set_property(GLOBAL APPEND PROPERTY GALE_BENCH_LIBS gale_render)
