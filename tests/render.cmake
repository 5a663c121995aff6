# gale_render tests (LABELS render): llvmpipe through EGL, or Xvfb (deploy/test.sh).
gale_test(test_render LABEL render SOURCES test_render.c LIBS gale_render TIMEOUT 300)
gale_test(test_falling_path LABEL unit SOURCES test_falling_path.c LIBS gale_render)
