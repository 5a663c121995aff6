# Scenario tests: Holland profile against its closed form and Andrew's figures, Saffir–Simpson
# boundaries, gust statistics and determinism, HURDAT2 parsing, scenario files and replays.
gale_test(test_holland LABEL unit SOURCES test_holland.c LIBS gale_scenario)
gale_test(test_saffir LABEL unit SOURCES test_saffir.c LIBS gale_scenario)
gale_test(test_gust LABEL unit SOURCES test_gust.c LIBS gale_scenario)
gale_test(test_hurdat LABEL unit SOURCES test_hurdat.c LIBS gale_scenario)
gale_test(test_scenario LABEL unit SOURCES test_scenario.c LIBS gale_scenario)
gale_fuzz(scenario LIBS gale_scenario)
# The scenario on the real solver, once it is in the tree.
if(TARGET gale_wind)
    gale_test(test_scenario_grid LABEL unit SOURCES test_scenario_grid.c
        LIBS gale_scenario gale_wind TIMEOUT 300)
endif()
