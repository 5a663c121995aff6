# The bake: skeleton -> FEM frame elements -> lowest modes -> wind basis -> strong-wind
# correction -> asset file (gale-bake), and the exact modal oscillator shared with the
# simulation.
add_library(gale_bake STATIC
    ${CMAKE_CURRENT_SOURCE_DIR}/oscillator.c)
target_include_directories(gale_bake PUBLIC ${CMAKE_CURRENT_SOURCE_DIR})
target_link_libraries(gale_bake PUBLIC gale_common ${MATH_LIB})
