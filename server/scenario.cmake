# Wind scenarios: Holland hurricane, gusts, Saffir–Simpson classes, HURDAT2 reader, and the
# gale-wind tool (timeline and slice picture) and gale-hurdat (best track → scenario JSON).
add_library(gale_scenario STATIC
    ${CMAKE_CURRENT_SOURCE_DIR}/scenario.c
    ${CMAKE_CURRENT_SOURCE_DIR}/scenario_apply.c
    ${CMAKE_CURRENT_SOURCE_DIR}/holland.c
    ${CMAKE_CURRENT_SOURCE_DIR}/gust.c
    ${CMAKE_CURRENT_SOURCE_DIR}/saffir.c
    ${CMAKE_CURRENT_SOURCE_DIR}/hurdat.c)
target_include_directories(gale_scenario PUBLIC ${CMAKE_CURRENT_SOURCE_DIR})
target_link_libraries(gale_scenario PUBLIC gale_common gale_protocol ${MATH_LIB})
# scenario_apply.c calls the solver; programs that use it link gale_wind once it exists.
if(TARGET gale_wind)
    target_link_libraries(gale_scenario PUBLIC gale_wind)
endif()

add_executable(gale-hurdat ${CMAKE_CURRENT_SOURCE_DIR}/hurdat_main.c)
target_link_libraries(gale-hurdat PRIVATE gale_scenario)

# gale-wind runs a scenario on the real solver and draws with the plot raster: built once
# both libraries are in the tree.
if(TARGET gale_wind AND TARGET gale_geom)
    add_executable(gale-wind ${CMAKE_CURRENT_SOURCE_DIR}/scenario_main.c)
    target_link_libraries(gale-wind PRIVATE gale_scenario gale_wind gale_geom)
endif()
