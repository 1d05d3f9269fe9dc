# nurbsgl_embed_glsl(<target> <function> <files...>)
# Generates a C++ source defining `std::span<const gpgpu::ShaderFile> <function>()` that holds the
# text of each file (named by its file name), and adds it to <target>. Shaders are read from the
# binary, never from the working directory; editing a .glsl file re-runs the generator.
function(nurbsgl_embed_glsl target function)
  set(out ${CMAKE_CURRENT_BINARY_DIR}/${function}.cpp)
  add_custom_command(
    OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -DOUT=${out} -DFUNCTION=${function} "-DFILES=${ARGN}"
            -P ${PROJECT_SOURCE_DIR}/cmake/embed_glsl_run.cmake
    DEPENDS ${ARGN} ${PROJECT_SOURCE_DIR}/cmake/embed_glsl_run.cmake
    COMMENT "Embedding GLSL for ${function}"
    VERBATIM)
  target_sources(${target} PRIVATE ${out})
endfunction()
