# The wire: binary frames (wire.c, msg_*.c) and JSON control (ctl.c). libc + cJSON only.
target_sources(gale_protocol PRIVATE
    ${CMAKE_CURRENT_LIST_DIR}/wire.c
    ${CMAKE_CURRENT_LIST_DIR}/msg_state.c
    ${CMAKE_CURRENT_LIST_DIR}/msg_leaves.c
    ${CMAKE_CURRENT_LIST_DIR}/msg_wind.c
    ${CMAKE_CURRENT_LIST_DIR}/ctl.c)
