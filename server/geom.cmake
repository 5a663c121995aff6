# Geometry of a tree: L-system skeletons, species files, skeleton CSV import, tube mesh
# and leaf slots, figures (plot), the asset file on disk; and gale-skelshot to look at them.
find_library(STB_LIB stb REQUIRED)
add_library(gale_geom STATIC
    ${CMAKE_CURRENT_LIST_DIR}/lsystem.c
    ${CMAKE_CURRENT_LIST_DIR}/species.c
    ${CMAKE_CURRENT_LIST_DIR}/skeleton_csv.c
    ${CMAKE_CURRENT_LIST_DIR}/mesh.c
    ${CMAKE_CURRENT_LIST_DIR}/plot.c
    ${CMAKE_CURRENT_LIST_DIR}/asset_file.c)
target_include_directories(gale_geom PUBLIC ${CMAKE_CURRENT_LIST_DIR})
target_link_libraries(gale_geom PUBLIC gale_common gale_protocol ${STB_LIB} ${MATH_LIB})

add_executable(gale-skelshot ${CMAKE_CURRENT_LIST_DIR}/skelshot_main.c)
target_link_libraries(gale-skelshot PRIVATE gale_geom)
