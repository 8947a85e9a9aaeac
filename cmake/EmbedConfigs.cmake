# Embeds every configs/**/*.yaml into the library, so `gyrosid run` and `builtin:` paths work from any
# directory without the source tree. The generated file is rebuilt whenever a config changes.

function(gyrosid_embed_configs target config_dir)
  file(GLOB_RECURSE config_files CONFIGURE_DEPENDS "${config_dir}/*.yaml")
  set(out "${CMAKE_CURRENT_BINARY_DIR}/generated/builtin_configs.cpp")
  add_custom_command(
    OUTPUT "${out}"
    COMMAND ${CMAKE_COMMAND} -DCONFIG_DIR=${config_dir} -DOUT=${out}
            -P ${PROJECT_SOURCE_DIR}/cmake/GenerateBuiltinConfigs.cmake
    DEPENDS ${config_files} ${PROJECT_SOURCE_DIR}/cmake/GenerateBuiltinConfigs.cmake
    COMMENT "Embedding configs/ into the gyrosid library"
    VERBATIM)
  target_sources(${target} PRIVATE "${out}")
endfunction()
