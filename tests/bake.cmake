# Bake: oscillator, FEM, eigen, wind basis, correction, gale-bake CLI.
gale_test(test_oscillator LABEL unit SOURCES test_oscillator.c LIBS gale_bake)
gale_test(test_fem LABEL unit SOURCES test_fem.c LIBS gale_bake)
gale_test(test_eigen LABEL unit SOURCES test_eigen.c LIBS gale_bake)
gale_test(test_basis LABEL unit SOURCES test_basis.c LIBS gale_bake)
gale_test(test_correction LABEL unit SOURCES test_correction.c LIBS gale_bake)
if(TARGET gale-bake)
    gale_test(test_bake_cli LABEL unit SOURCES test_bake_cli.c LIBS gale_bake PkgConfig::CJSON
        TIMEOUT 300)
    target_compile_definitions(test_bake_cli PRIVATE GALE_BAKE_EXE="$<TARGET_FILE:gale-bake>")
    add_dependencies(test_bake_cli gale-bake)
endif()
