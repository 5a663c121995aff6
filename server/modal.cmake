# The batch modal state of every tree (gale_modal) and its benchmarks: gale-bench modal
# (per-tick update of many trees) and gale-bench wire (bytes per tree and node error).
add_library(gale_modal STATIC ${CMAKE_CURRENT_LIST_DIR}/modal.c)
target_include_directories(gale_modal PUBLIC ${CMAKE_CURRENT_LIST_DIR})
target_link_libraries(gale_modal PUBLIC gale_bake gale_protocol OpenMP::OpenMP_C ${MATH_LIB})
set_property(GLOBAL APPEND PROPERTY GALE_BENCH_SOURCES
    ${CMAKE_CURRENT_LIST_DIR}/bench_modal.c ${CMAKE_CURRENT_LIST_DIR}/bench_wire.c)
set_property(GLOBAL APPEND PROPERTY GALE_BENCH_LIBS gale_modal gale_bake gale_geom gale_scenario gale_wind gale_protocol)
# Without trapping math gcc if-converts the clamps of the quantiser and vectorises the
# per-mode lane loop (modal.c uses no floating-point exception flags).
set_source_files_properties(${CMAKE_CURRENT_LIST_DIR}/modal.c PROPERTIES
    COMPILE_OPTIONS "-fno-trapping-math")
