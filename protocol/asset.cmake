# The asset file format (ASSET.md) and the content hashes it uses.
target_sources(gale_protocol PRIVATE
    ${CMAKE_CURRENT_LIST_DIR}/asset.c
    ${CMAKE_CURRENT_LIST_DIR}/hash.c)
