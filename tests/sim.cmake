# Scene config, leaf shedding, send queues, tick loop; loopback server integration tests.
gale_test(test_scene LABEL unit SOURCES test_scene.c LIBS gale_sim TIMEOUT 60)
gale_fuzz(scene LIBS gale_sim)
target_include_directories(fuzz_scene PRIVATE ${CMAKE_SOURCE_DIR}/server)
