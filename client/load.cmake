# gale-load: the headless load client (protocol library + libwebsockets only).
add_executable(gale-load ${CMAKE_CURRENT_LIST_DIR}/load_main.c)
target_link_libraries(gale-load PRIVATE gale_protocol PkgConfig::LWS)
