# gale-client: networking, jitter buffer, asset cache, HUD, camera (gale_client library),
# the gale-client executable and the client CPU benchmark.
add_library(gale_client STATIC
    ${CMAKE_CURRENT_LIST_DIR}/jitter.c
    ${CMAKE_CURRENT_LIST_DIR}/asset_cache.c)
target_include_directories(gale_client PUBLIC ${CMAKE_CURRENT_LIST_DIR})
target_link_libraries(gale_client PUBLIC gale_protocol ${MATH_LIB})
