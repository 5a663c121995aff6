# Bake: oscillator, FEM, eigen, wind basis, correction, gale-bake CLI.
gale_test(test_oscillator LABEL unit SOURCES test_oscillator.c LIBS gale_bake)
gale_test(test_fem LABEL unit SOURCES test_fem.c LIBS gale_bake)
gale_test(test_eigen LABEL unit SOURCES test_eigen.c LIBS gale_bake)
gale_test(test_basis LABEL unit SOURCES test_basis.c LIBS gale_bake)
gale_test(test_correction LABEL unit SOURCES test_correction.c LIBS gale_bake)
