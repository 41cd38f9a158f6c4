# The layers' one-way rule as data: what a target links, directly or through the targets it links
# (public and private), read from the targets themselves at configure time. The top-level
# CMakeLists.txt states the rules with s4d_forbid_links, which stops configuration at a breach.

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

# s4d_forbid_links(RULE <why> TARGETS <t>... FORBIDDEN <lib>... REQUIRED <lib>): stops configuration
# naming the rule, each target and the library it must not link when a target's closure holds a
# FORBIDDEN library, or lacks REQUIRED (which every target links: a closure without it means the walk
# itself is broken, and a pass would mean nothing). Targets that this build leaves out are skipped.
function(s4d_forbid_links)
  cmake_parse_arguments(ARG "" "RULE;REQUIRED" "TARGETS;FORBIDDEN" ${ARGN})
  set(bad "")
  set(checked 0)
  foreach(t IN LISTS ARG_TARGETS)
    if(NOT TARGET ${t})
      continue()
    endif()
    math(EXPR checked "${checked} + 1")
    s4d_link_closure(${t} deps)
    if(NOT ARG_REQUIRED IN_LIST deps)
      list(APPEND bad "  ${t} does not reach ${ARG_REQUIRED} (the link walk is broken)")
    endif()
    foreach(f IN LISTS ARG_FORBIDDEN)
      if(f IN_LIST deps)
        list(APPEND bad "  ${t} links ${f}")
      endif()
    endforeach()
  endforeach()
  if(checked EQUAL 0)
    message(FATAL_ERROR "layer rule '${ARG_RULE}': none of its targets (${ARG_TARGETS}) exists")
  endif()
  if(bad)
    list(JOIN bad "\n" bad)
    message(FATAL_ERROR "layer rule broken: ${ARG_RULE} (docs/layout.md \"Layers\"):\n${bad}\n"
                        "A library a target links directly or through others is listed; move what the target "
                        "needs below the forbidden library, or link it from a program outside the rule.")
  endif()
  list(JOIN ARG_FORBIDDEN ", " forbidden)
  message(STATUS "Layers: ${checked} target(s) link none of ${forbidden} (${ARG_RULE})")
endfunction()
