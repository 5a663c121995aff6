# The simulation and serving: scene config, tick loop, leaf shedding, per-connection send
# queues, lws serving (gale_sim), and the gale-server executable.
set(GALE_SCENE_EMBED ${CMAKE_CURRENT_BINARY_DIR}/scene_default_json.c)
add_custom_command(OUTPUT ${GALE_SCENE_EMBED}
    COMMAND ${CMAKE_COMMAND} -DIN=${CMAKE_SOURCE_DIR}/configs/scenes/default.json
        -DOUT=${GALE_SCENE_EMBED} -DNAME=scene_default_json
        -P ${CMAKE_CURRENT_SOURCE_DIR}/embed.cmake
    DEPENDS ${CMAKE_SOURCE_DIR}/configs/scenes/default.json
        ${CMAKE_CURRENT_SOURCE_DIR}/embed.cmake
    COMMENT "Embedding configs/scenes/default.json")

add_library(gale_sim STATIC
    ${CMAKE_CURRENT_SOURCE_DIR}/scene.c
    ${CMAKE_CURRENT_SOURCE_DIR}/leaf.c
    ${CMAKE_CURRENT_SOURCE_DIR}/sendq.c
    ${CMAKE_CURRENT_SOURCE_DIR}/net.c
    ${CMAKE_CURRENT_SOURCE_DIR}/tick.c
    ${CMAKE_CURRENT_SOURCE_DIR}/srv.c
    ${GALE_SCENE_EMBED})
target_include_directories(gale_sim PUBLIC ${CMAKE_CURRENT_SOURCE_DIR})
target_link_libraries(gale_sim PUBLIC gale_common gale_scenario gale_protocol PkgConfig::LWS
    Threads::Threads ${MATH_LIB})

# gale-server needs the bake (species -> asset), the geometry (L-system, species files,
# asset files) and the wind solver; it is built once those areas are in the tree.
if(TARGET gale_wind AND TARGET gale_geom AND EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/bake.c)
    add_executable(gale-server
        ${CMAKE_CURRENT_SOURCE_DIR}/srv_main.c
        ${CMAKE_CURRENT_SOURCE_DIR}/species_cache.c)
    target_link_libraries(gale-server PRIVATE gale_sim gale_bake gale_geom gale_wind)
endif()
