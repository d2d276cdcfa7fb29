# Embeds every file under shaders/ into a generated C++ source as a string table,
# so the binary needs no shader files at run time.
function(pluvia_embed_shaders out_cpp)
  file(GLOB shader_files CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/shaders/*)
  add_custom_command(
    OUTPUT ${out_cpp}
    COMMAND ${CMAKE_COMMAND} -DOUT=${out_cpp} -DSHADER_DIR=${CMAKE_SOURCE_DIR}/shaders
            -P ${CMAKE_SOURCE_DIR}/cmake/embed_shaders_run.cmake
    DEPENDS ${shader_files} ${CMAKE_SOURCE_DIR}/cmake/embed_shaders_run.cmake
    COMMENT "Embedding shaders")
endfunction()
