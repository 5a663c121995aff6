# Client application: jitter buffer, asset cache, HUD, camera; integration with gale-server.
gale_test(test_jitter LABEL unit SOURCES test_jitter.c LIBS gale_client)
gale_test(test_asset_cache LABEL unit SOURCES test_asset_cache.c LIBS gale_client)
gale_test(test_hud LABEL render SOURCES test_hud.c LIBS gale_client PkgConfig::GLFW)
gale_test(test_camera LABEL unit SOURCES test_camera.c LIBS gale_client)
gale_test(test_client_net LABEL net SOURCES test_client_net.c LIBS gale_client Threads::Threads TIMEOUT 60)
