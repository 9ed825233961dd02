# puff_embed_files(TARGET name ROOT dir FILES f1 f2 ... NAMESPACE ns)
# Generates a C++ source that holds each file's bytes, keyed by its path relative to ROOT, and adds
# it to TARGET. The table is exposed through `puff::core::embedded*` (see shader.h).
function(puff_embed_files target)
  cmake_parse_arguments(E "" "ROOT;SYMBOL" "FILES" ${ARGN})
  set(out ${CMAKE_CURRENT_BINARY_DIR}/${E_SYMBOL}_embedded.cpp)
  add_custom_command(
    OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -DROOT=${E_ROOT} -DOUT=${out} -DSYMBOL=${E_SYMBOL} "-DFILES=${E_FILES}"
            -P ${PROJECT_SOURCE_DIR}/cmake/EmbedFilesScript.cmake
    DEPENDS ${E_FILES} ${PROJECT_SOURCE_DIR}/cmake/EmbedFilesScript.cmake
    COMMENT "Embedding ${E_SYMBOL} files" VERBATIM)
  target_sources(${target} PRIVATE ${out})
endfunction()
