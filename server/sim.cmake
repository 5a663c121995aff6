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
    ${GALE_SCENE_EMBED})
target_include_directories(gale_sim PUBLIC ${CMAKE_CURRENT_SOURCE_DIR})
target_link_libraries(gale_sim PUBLIC gale_common gale_protocol PkgConfig::LWS
    Threads::Threads ${MATH_LIB})
