# gale-bench: each area appends its bench_<name>.c and libraries to these properties.
get_property(GALE_BENCH_SOURCES GLOBAL PROPERTY GALE_BENCH_SOURCES)
get_property(GALE_BENCH_LIBS GLOBAL PROPERTY GALE_BENCH_LIBS)
add_executable(gale-bench ${CMAKE_SOURCE_DIR}/server/bench_main.c ${GALE_BENCH_SOURCES})
target_link_libraries(gale-bench PRIVATE ${GALE_BENCH_LIBS})
