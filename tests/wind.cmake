# Wind field: projection tolerance, solid faces, inflow, advection, determinism, sampling.
gale_test(test_wind LABEL unit SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_wind.c LIBS gale_wind
    TIMEOUT 300)
