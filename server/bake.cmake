# The bake: skeleton -> FEM frame elements -> lowest modes -> wind basis -> strong-wind
# correction -> asset file (gale-bake), and the exact modal oscillator shared with the
# simulation.
add_library(gale_bake STATIC
    ${CMAKE_CURRENT_SOURCE_DIR}/oscillator.c
    ${CMAKE_CURRENT_SOURCE_DIR}/fem.c
    ${CMAKE_CURRENT_SOURCE_DIR}/tree_chol.c
    ${CMAKE_CURRENT_SOURCE_DIR}/eigen.c
    ${CMAKE_CURRENT_SOURCE_DIR}/basis.c
    ${CMAKE_CURRENT_SOURCE_DIR}/correction.c
    ${CMAKE_CURRENT_SOURCE_DIR}/bake_tree.c)
target_include_directories(gale_bake PUBLIC ${CMAKE_CURRENT_SOURCE_DIR})
target_link_libraries(gale_bake PUBLIC gale_common ${ARPACK_LIB} ${LAPACKE_LIB} ${OPENBLAS_LIB}
    ${MATH_LIB})
