# Geometry: L-system, species files, plot; fuzz replays of the text parsers.
gale_test(test_lsystem LABEL unit SOURCES test_lsystem.c LIBS gale_geom)
gale_test(test_species LABEL unit SOURCES test_species.c LIBS gale_geom)
gale_test(test_plot LABEL unit SOURCES test_plot.c LIBS gale_geom)
