# Writes version.hpp (and, with PY_DST, the Python package's _version.py) from `git describe` at every
# build, touching them only on change. The version: the describe of the last tag vX.Y.Z without its
# "v" ("0.1.0", "0.1.0-3-g1234abc", "-dirty" with uncommitted changes); without a tag (a shallow
# clone, a tarball) PROJECT_VERSION+g<hash>.
execute_process(COMMAND git describe --always --dirty WORKING_DIRECTORY ${SRC_DIR}
                OUTPUT_VARIABLE ROTLEAK_GIT OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
execute_process(COMMAND git describe --tags --match "v[0-9]*" --dirty WORKING_DIRECTORY ${SRC_DIR}
                OUTPUT_VARIABLE ROTLEAK_DESCRIBE OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(NOT ROTLEAK_GIT)
  set(ROTLEAK_GIT "unknown")
endif()
if(ROTLEAK_DESCRIBE MATCHES "^v([0-9].*)$")
  set(ROTLEAK_VERSION_STRING "${CMAKE_MATCH_1}")
elseif(ROTLEAK_GIT STREQUAL "unknown")
  set(ROTLEAK_VERSION_STRING "${PROJECT_VERSION}")
else()
  set(ROTLEAK_VERSION_STRING "${PROJECT_VERSION}+g${ROTLEAK_GIT}")
endif()
set(CMAKE_SOURCE_DIR ${SRC_DIR})
foreach(pair "version.hpp.in;${DST}" "rotleak/_version.py.in;${PY_DST}")
  list(GET pair 0 in)
  list(GET pair 1 out)
  if(out)
    if(in MATCHES "\\.py\\.in$")
      set(in_path ${SRC_DIR}/python/${in})
    else()
      set(in_path ${SRC_DIR}/src/${in})
    endif()
    configure_file(${in_path} ${out}.tmp @ONLY)
    execute_process(COMMAND ${CMAKE_COMMAND} -E copy_if_different ${out}.tmp ${out})
    file(REMOVE ${out}.tmp)
  endif()
endforeach()
