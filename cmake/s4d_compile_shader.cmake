# Compiles one shader variant: glslc (any output fails), spirv-val, then embeds the words in a .cpp.
execute_process(
  COMMAND ${GLSLC} -fshader-stage=compute --target-env=vulkan1.2 -Werror -MD -MF ${DEP} -MT ${CPP}
          ${FLAGS} ${SRC} -o ${SPV}
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT "${out}${err}" STREQUAL "")
  file(REMOVE ${SPV} ${CPP})
  message(FATAL_ERROR "glslc failed or printed diagnostics for ${SRC}:\n${out}${err}")
endif()
execute_process(COMMAND ${SPIRV_VAL} --target-env vulkan1.2 ${SPV}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  file(REMOVE ${SPV} ${CPP})
  message(FATAL_ERROR "spirv-val rejected ${SPV}:\n${out}${err}")
endif()

file(READ ${SPV} hex HEX)
string(LENGTH "${hex}" hex_len)
math(EXPR words "${hex_len} / 8")
# SPIR-V words are little endian: reverse the byte order of each 8-hex-digit group.
string(REGEX REPLACE "(..)(..)(..)(..)" "0x\\4\\3\\2\\1u," body "${hex}")
string(REGEX REPLACE "(([^,]*,){8})" "\\1\n  " body "${body}")
file(WRITE ${CPP}.tmp
"// Generated from ${SRC}; do not edit.\n#include <cstddef>\n#include <cstdint>\nnamespace s4d::shaders {\nextern const uint32_t ${NAME}_spv[];\nextern const size_t ${NAME}_spv_words;\nalignas(16) const uint32_t ${NAME}_spv[] = {\n  ${body}\n};\nconst size_t ${NAME}_spv_words = ${words};\n}\n")
file(RENAME ${CPP}.tmp ${CPP})
