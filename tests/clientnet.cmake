# Client application: jitter buffer, asset cache, HUD, camera; integration with gale-server.
gale_test(test_jitter LABEL unit SOURCES test_jitter.c LIBS gale_client)
gale_test(test_asset_cache LABEL unit SOURCES test_asset_cache.c LIBS gale_client)
gale_test(test_hud LABEL render SOURCES test_hud.c LIBS gale_client PkgConfig::GLFW)
gale_test(test_camera LABEL unit SOURCES test_camera.c LIBS gale_client)
gale_test(test_client_net LABEL net SOURCES test_client_net.c LIBS gale_client Threads::Threads TIMEOUT 60)

# Live tests against the real gale-server and gale-client (built once both areas are in).
if(TARGET gale-server AND TARGET gale-client)
    gale_test(test_client_live LABEL net SOURCES test_client_live.c LIBS gale_client
        TIMEOUT 900)
    target_compile_definitions(test_client_live PRIVATE
        GALE_SERVER_EXE="$<TARGET_FILE:gale-server>" GALE_CLIENT_EXE="$<TARGET_FILE:gale-client>")
    add_dependencies(test_client_live gale-server gale-client)
    set_tests_properties(test_client_live PROPERTIES SKIP_RETURN_CODE 77)
endif()
