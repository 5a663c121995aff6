# Turns the browser client's files into one C table (net_web.c serves it):
# cmake -DOUT=file.c -DFILES="url=path|url=path|..." -P web_embed.cmake
# Each file becomes an array, as embed.cmake does for the default scene, so gale-server
# alone serves the pages with no files beside it.
set(decls "")
set(rows "")
set(i 0)
string(REPLACE "|" ";" pairs "${FILES}")
foreach(pair ${pairs})
    string(FIND "${pair}" "=" eq)
    string(SUBSTRING "${pair}" 0 ${eq} url)
    math(EXPR from "${eq} + 1")
    string(SUBSTRING "${pair}" ${from} -1 path)
    file(READ "${path}" hex HEX)
    string(LENGTH "${hex}" n)
    math(EXPR bytes "${n} / 2")
    string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," body "${hex}")
    string(APPEND decls "static const unsigned char web_file_${i}[] = {${body}0x00};\n")
    string(APPEND rows "    { \"${url}\", web_file_${i}, ${bytes} },\n")
    math(EXPR i "${i} + 1")
endforeach()
file(WRITE "${OUT}.tmp" "/* Embedded copy of web/ and shaders/ (server/serve/web_embed.cmake). */\n"
    "#include \"net_web.h\"\n\n${decls}\nconst net_web_file net_web_files[] = {\n${rows}};\n"
    "const int net_web_n_files = ${i};\n")
# Written only when it changed, so a rebuild does not recompile an unchanged table.
file(COPY_FILE "${OUT}.tmp" "${OUT}" ONLY_IF_DIFFERENT)
file(REMOVE "${OUT}.tmp")
