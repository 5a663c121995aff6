# Bake: oscillator, FEM, eigen, wind basis, correction, gale-bake CLI.
gale_test(test_oscillator LABEL unit SOURCES test_oscillator.c LIBS gale_bake)
gale_test(test_fem LABEL unit SOURCES test_fem.c LIBS gale_bake)
