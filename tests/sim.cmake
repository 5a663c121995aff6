# Scene config, leaf shedding, send queues, tick loop; loopback server integration tests.
gale_test(test_scene LABEL unit SOURCES test_scene.c LIBS gale_sim TIMEOUT 60)
gale_fuzz(scene LIBS gale_sim)
target_include_directories(fuzz_scene PRIVATE ${CMAKE_SOURCE_DIR}/server)
gale_test(test_server_sendq LABEL unit SOURCES test_server_sendq.c LIBS gale_sim TIMEOUT 30)
gale_test(test_server_leaf LABEL unit SOURCES test_server_leaf.c LIBS gale_sim TIMEOUT 30)
gale_test(test_server_tick LABEL unit SOURCES test_server_tick.c LIBS gale_sim TIMEOUT 30)
