# s4d_set_warnings(target): the project's warning set; -Werror when S4D_WERROR is on (CI).
function(s4d_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
                         -Wno-sign-conversion -Wnon-virtual-dtor -Wold-style-cast
                         # designated initialisers of Vk*Info structs zero the rest on purpose
                         -Wno-missing-field-initializers)
  if(S4D_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()
