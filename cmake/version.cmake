# Writes version.hpp with the current `git describe` at every build, touching it only on change.
execute_process(COMMAND git describe --always --dirty WORKING_DIRECTORY ${SRC_DIR}
                OUTPUT_VARIABLE ROTLEAK_GIT OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(NOT ROTLEAK_GIT)
  set(ROTLEAK_GIT "unknown")
endif()
set(CMAKE_SOURCE_DIR ${SRC_DIR})
configure_file(${SRC_DIR}/src/version.hpp.in ${DST}.tmp @ONLY)
execute_process(COMMAND ${CMAKE_COMMAND} -E copy_if_different ${DST}.tmp ${DST})
file(REMOVE ${DST}.tmp)
