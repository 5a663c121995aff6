# Wind field: stable fluids on a MAC grid with a multigrid pressure solve (wind.h).
add_library(gale_wind STATIC
    ${CMAKE_CURRENT_SOURCE_DIR}/wind.c
    ${CMAKE_CURRENT_SOURCE_DIR}/wind_advect.c
    ${CMAKE_CURRENT_SOURCE_DIR}/wind_mg.c)
target_include_directories(gale_wind PUBLIC ${CMAKE_CURRENT_SOURCE_DIR})
# The row kernels are written to vectorise; -O3 lets gcc do it (the default -O2 of gcc 12
# vectorises only trivially cheap loops).
target_compile_options(gale_wind PRIVATE $<$<CONFIG:RelWithDebInfo,Release>:-O3>)
target_link_libraries(gale_wind PUBLIC gale_protocol OpenMP::OpenMP_C ${MATH_LIB})

set_property(GLOBAL APPEND PROPERTY GALE_BENCH_SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/bench_wind.c)
set_property(GLOBAL APPEND PROPERTY GALE_BENCH_LIBS gale_wind)
