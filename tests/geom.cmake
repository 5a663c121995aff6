# Geometry: L-system, species files, plot; fuzz replays of the text parsers.
gale_test(test_lsystem LABEL unit SOURCES test_lsystem.c LIBS gale_geom)
gale_test(test_species LABEL unit SOURCES test_species.c LIBS gale_geom)
gale_test(test_plot LABEL unit SOURCES test_plot.c LIBS gale_geom)
gale_test(test_asset LABEL unit SOURCES test_asset.c LIBS gale_geom)
gale_fuzz(asset LIBS gale_protocol)
gale_test(test_skeleton_csv LABEL unit SOURCES test_skeleton_csv.c LIBS gale_geom)
gale_fuzz(skeleton_csv LIBS gale_geom)
gale_fuzz(species LIBS gale_geom)
gale_test(test_mesh LABEL unit SOURCES test_mesh.c LIBS gale_geom)

# gale-skelshot draws every shipped species and a CSV skeleton; bad input exits non-zero.
foreach(sp oak palm pine)
    add_test(NAME skelshot_${sp} COMMAND gale-skelshot
        --species ${CMAKE_SOURCE_DIR}/configs/species/${sp}.json --out skelshot_${sp}.png)
    set_tests_properties(skelshot_${sp} PROPERTIES LABELS unit TIMEOUT 60)
endforeach()
add_test(NAME skelshot_csv COMMAND gale-skelshot
    --skeleton ${CMAKE_CURRENT_SOURCE_DIR}/fuzz/corpus/skeleton_csv/small.csv --out skelshot_csv.png)
add_test(NAME skelshot_bad_csv COMMAND gale-skelshot
    --skeleton ${CMAKE_CURRENT_SOURCE_DIR}/fuzz/corpus/skeleton_csv/cycle.csv --out skelshot_bad.png)
add_test(NAME skelshot_no_out COMMAND gale-skelshot
    --species ${CMAKE_SOURCE_DIR}/configs/species/oak.json)
set_tests_properties(skelshot_csv skelshot_bad_csv skelshot_no_out PROPERTIES LABELS unit TIMEOUT 60)
set_tests_properties(skelshot_bad_csv skelshot_no_out PROPERTIES WILL_FAIL TRUE)
gale_test(test_species_physics LABEL unit SOURCES test_species_physics.c LIBS gale_bake TIMEOUT 120)
