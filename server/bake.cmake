# The bake: skeleton -> FEM frame elements -> lowest modes -> wind basis -> strong-wind
# correction -> asset file (gale-bake), and the exact modal oscillator shared with the
# simulation. The pipeline, gale-bake and its benchmark need the geometry library.
add_library(gale_bake STATIC
    ${CMAKE_CURRENT_SOURCE_DIR}/oscillator.c
    ${CMAKE_CURRENT_SOURCE_DIR}/fem.c
    ${CMAKE_CURRENT_SOURCE_DIR}/tree_chol.c
    ${CMAKE_CURRENT_SOURCE_DIR}/eigen.c
    ${CMAKE_CURRENT_SOURCE_DIR}/basis.c
    ${CMAKE_CURRENT_SOURCE_DIR}/correction.c
    ${CMAKE_CURRENT_SOURCE_DIR}/bake_tree.c)
target_include_directories(gale_bake PUBLIC ${CMAKE_CURRENT_SOURCE_DIR})
target_link_libraries(gale_bake PUBLIC gale_common OpenMP::OpenMP_C ${ARPACK_LIB} ${LAPACKE_LIB} ${OPENBLAS_LIB}
    ${MATH_LIB})

if(TARGET gale_geom)
    target_sources(gale_bake PRIVATE
        ${CMAKE_CURRENT_SOURCE_DIR}/bake.c
        ${CMAKE_CURRENT_SOURCE_DIR}/modes_png.c)
    target_link_libraries(gale_bake PUBLIC gale_geom PkgConfig::CJSON)
    add_executable(gale-bake ${CMAKE_CURRENT_SOURCE_DIR}/bake_main.c)
    target_link_libraries(gale-bake PRIVATE gale_bake)
    set_property(GLOBAL APPEND PROPERTY GALE_BENCH_SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/bench_bake.c)
    set_property(GLOBAL APPEND PROPERTY GALE_BENCH_LIBS gale_bake)
endif()
