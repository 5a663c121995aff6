# protocol/ (binary wire, JSON control) and server/modal.c tests, plus their fuzz replays.
gale_test(test_wire LABEL unit SOURCES test_wire.c LIBS gale_protocol)
gale_test(test_ctl LABEL unit SOURCES test_ctl.c LIBS gale_protocol)
if(TARGET gale_modal)
    gale_test(test_modal LABEL unit SOURCES test_modal.c LIBS gale_modal)
endif()
gale_fuzz(wire LIBS gale_protocol)
gale_fuzz(ctl LIBS gale_protocol)
