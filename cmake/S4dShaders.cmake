# Build-time GLSL -> SPIR-V -> embedded C++ arrays.
#
# s4d_add_shader_library(TARGET VARIANTS_FILE) reads a variant table (see shaders/variants.cmake):
# each entry compiles one .comp with a set of defines. Every variant is compiled with glslc using
# a depfile (so edits to included headers rebuild exactly the shaders that include them), validated
# with spirv-val, and turned into a .cpp holding a uint32_t array. Any text glslc prints fails the
# build (warnings included), following ggml's rule that shader diagnostics are never ignored.

find_program(S4D_GLSLC glslc REQUIRED)
find_program(S4D_SPIRV_VAL spirv-val REQUIRED)

set(S4D_SHADER_SCRIPTS_DIR ${CMAKE_CURRENT_LIST_DIR})

function(s4d_add_shader_library target)
  cmake_parse_arguments(ARG "" "SOURCE_DIR" "VARIANTS" ${ARGN})
  set(gen_dir ${CMAKE_CURRENT_BINARY_DIR}/generated)
  file(MAKE_DIRECTORY ${gen_dir}/s4d)
  # No glslc -O: it strips OpName/OpMemberName, which the layout tests and debuggers read, and
  # every driver optimises the SPIR-V again anyway.
  set(opt_flag -O0)
  if(S4D_SHADER_DEBUG_INFO)
    set(opt_flag -g -O0)
  endif()

  set(cpp_files "")
  set(names "")
  list(LENGTH ARG_VARIANTS n)
  math(EXPR last "${n} - 1")
  foreach(i RANGE 0 ${last})
    list(GET ARG_VARIANTS ${i} entry)
    string(REPLACE "|" ";" fields "${entry}")
    list(GET fields 0 name)
    list(GET fields 1 src)
    list(LENGTH fields nfields)
    set(defines "")
    if(nfields GREATER 2)
      list(SUBLIST fields 2 -1 defines)
    endif()
    set(define_flags "")
    foreach(d ${defines})
      list(APPEND define_flags "-D${d}")
    endforeach()
    set(spv ${gen_dir}/${name}.spv)
    set(dep ${gen_dir}/${name}.spv.d)
    set(cpp ${gen_dir}/${name}.spv.cpp)
    add_custom_command(
      OUTPUT ${cpp}
      COMMAND ${CMAKE_COMMAND} -DGLSLC=${S4D_GLSLC} -DSPIRV_VAL=${S4D_SPIRV_VAL}
              -DSRC=${ARG_SOURCE_DIR}/${src} -DSPV=${spv} -DDEP=${dep} -DCPP=${cpp} -DNAME=${name}
              "-DFLAGS=${opt_flag};${define_flags};-I${ARG_SOURCE_DIR}/shared;-I${ARG_SOURCE_DIR}/include"
              -P ${S4D_SHADER_SCRIPTS_DIR}/s4d_compile_shader.cmake
      DEPENDS ${ARG_SOURCE_DIR}/${src} ${S4D_SHADER_SCRIPTS_DIR}/s4d_compile_shader.cmake
      DEPFILE ${dep}
      COMMENT "glslc ${name}"
      VERBATIM)
    list(APPEND cpp_files ${cpp})
    list(APPEND names ${name})
  endforeach()

  # Registry: enum class Id + lookup table, generated from the variant names.
  set(enum_body "")
  set(decl_body "")
  set(table_body "")
  foreach(name ${names})
    string(APPEND enum_body "  ${name},\n")
    string(APPEND decl_body "extern const uint32_t ${name}_spv[];\nextern const size_t ${name}_spv_words;\n")
    string(APPEND table_body "    {\"${name}\", ${name}_spv, ${name}_spv_words},\n")
  endforeach()
  configure_file(${S4D_SHADER_SCRIPTS_DIR}/shader_registry.h.in ${gen_dir}/s4d/shader_registry.h @ONLY)
  configure_file(${S4D_SHADER_SCRIPTS_DIR}/shader_registry.cpp.in ${gen_dir}/shader_registry.cpp @ONLY)

  add_library(${target} STATIC ${cpp_files} ${gen_dir}/shader_registry.cpp)
  target_include_directories(${target} PUBLIC ${gen_dir})
endfunction()
