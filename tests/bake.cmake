# Bake: oscillator, FEM, eigen, wind basis, correction, gale-bake CLI.
gale_test(test_oscillator LABEL unit SOURCES test_oscillator.c LIBS gale_bake)
