# Scene config, leaf shedding, send queues, tick loop; loopback server integration tests.
gale_test(test_scene LABEL unit SOURCES test_scene.c LIBS gale_sim TIMEOUT 60)
gale_fuzz(scene LIBS gale_sim)
target_include_directories(fuzz_scene PRIVATE ${CMAKE_SOURCE_DIR}/server)
gale_test(test_server_sendq LABEL unit SOURCES test_server_sendq.c LIBS gale_sim TIMEOUT 30)
gale_test(test_server_leaf LABEL unit SOURCES test_server_leaf.c LIBS gale_sim TIMEOUT 30)
gale_test(test_server_tick LABEL unit SOURCES test_server_tick.c LIBS gale_sim TIMEOUT 30)
gale_test(test_server_net LABEL net SOURCES test_server_net.c LIBS gale_sim TIMEOUT 60)
gale_test(test_server_load LABEL net SOURCES test_server_load.c LIBS gale_sim TIMEOUT 60)
add_dependencies(test_server_load gale-load)
target_compile_definitions(test_server_load PRIVATE GALE_LOAD_EXE="$<TARGET_FILE:gale-load>")
if(TARGET gale-server)
    gale_test(test_server_sigterm LABEL net SOURCES test_server_sigterm.c LIBS gale_protocol
        TIMEOUT 120)
    add_dependencies(test_server_sigterm gale-server)
    target_compile_definitions(test_server_sigterm PRIVATE
        GALE_SERVER_EXE="$<TARGET_FILE:gale-server>")
endif()
