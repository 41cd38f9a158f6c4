# The layers' one-way rule as data: what a target links, directly or through the targets it links
# (public and private), read from the targets themselves at configure time. tests/CMakeLists.txt
# writes it for the render side and the bench's report, and cmake/check_layers.cmake refuses a
# forbidden library in it.

# s4d_link_closure(<target> <out-var>): the s4d_* targets that <target> links, sorted.
function(s4d_link_closure target out)
  set(seen "")
  set(todo ${target})
  while(todo)
    list(POP_FRONT todo t)
    get_target_property(type ${t} TYPE)
    set(links "")
    if(NOT type STREQUAL "INTERFACE_LIBRARY")
      get_target_property(links ${t} LINK_LIBRARIES)
    endif()
    get_target_property(interface ${t} INTERFACE_LINK_LIBRARIES)
    foreach(dep IN LISTS links interface)
      # Private links of a static library appear as $<LINK_ONLY:dep>; links made from another
      # directory are bracketed by ::@(dir) markers.
      string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" dep "${dep}")
      if(dep MATCHES "^s4d_" AND TARGET ${dep} AND NOT dep IN_LIST seen)
        list(APPEND seen ${dep})
        list(APPEND todo ${dep})
      endif()
    endforeach()
  endwhile()
  list(SORT seen)
  set(${out} ${seen} PARENT_SCOPE)
endfunction()

# s4d_write_link_closures(<file> <targets>...): one line per target, "target: dep dep ...".
function(s4d_write_link_closures file)
  set(text "")
  foreach(t IN LISTS ARGN)
    s4d_link_closure(${t} deps)
    list(JOIN deps " " deps)
    string(APPEND text "${t}: ${deps}\n")
  endforeach()
  file(WRITE ${file} "${text}")
endfunction()
