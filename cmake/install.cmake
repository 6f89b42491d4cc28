# cmake --install build --prefix P (and cpack) lays rotleak out as:
#   P/bin/rotleak
#   P/lib/librotleak_*.a, P/include/rotleak/...  and  P/lib/cmake/rotleak (find_package(rotleak): rotleak::core ...)
#   P/share/rotleak/data/{scenes,study,literature,trajectories}   (found by the binary relative to itself)
#   P/lib/python3/dist-packages/rotleak (readers, plots, the in-process module)
#   P/share/doc/rotleak (README, LICENSE, CITATION.cff)
include(CMakePackageConfigHelpers)

install(TARGETS rotleak RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS rotleak_core rotleak_analysis rotleak_io rotleak_verify rotleak_run rotleak_options rotleak_warnings
        EXPORT rotleakTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
set_target_properties(rotleak_options PROPERTIES EXPORT_NAME options)
set_target_properties(rotleak_warnings PROPERTIES EXPORT_NAME warnings)

# headers keep the paths the sources include them by ("sim/engine/engine.hpp", "analysis/fits.hpp")
install(DIRECTORY ${CMAKE_SOURCE_DIR}/src/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/rotleak
        FILES_MATCHING PATTERN "*.hpp" PATTERN "*.ipp")
foreach(layer analysis verify app/run)
  get_filename_component(name ${layer} NAME)
  install(DIRECTORY ${CMAKE_SOURCE_DIR}/${layer}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/rotleak/${name}
          FILES_MATCHING PATTERN "*.hpp" PATTERN "*.ipp")
endforeach()
install(FILES ${CMAKE_BINARY_DIR}/src/generated/version.hpp DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/rotleak)

install(EXPORT rotleakTargets NAMESPACE rotleak:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/rotleak)
configure_package_config_file(${CMAKE_SOURCE_DIR}/cmake/rotleakConfig.cmake.in
                              ${CMAKE_BINARY_DIR}/rotleakConfig.cmake
                              INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/rotleak
                              PATH_VARS CMAKE_INSTALL_DATADIR)
write_basic_package_version_file(${CMAKE_BINARY_DIR}/rotleakConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/rotleakConfig.cmake ${CMAKE_BINARY_DIR}/rotleakConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/rotleak)

# the data the commands read: scenes, the study's inputs, the published tables, the reference trajectories
install(DIRECTORY ${CMAKE_SOURCE_DIR}/data/ DESTINATION ${CMAKE_INSTALL_DATADIR}/rotleak/data)
install(FILES ${CMAKE_SOURCE_DIR}/README.md ${CMAKE_SOURCE_DIR}/LICENSE ${CMAKE_SOURCE_DIR}/CITATION.cff
        DESTINATION ${CMAKE_INSTALL_DOCDIR})

# cpack -G DEB (in the build directory): one package, rotleak, installed under /usr: the command, the
# Python package (Debian's python3 finds it in /usr/lib/python3/dist-packages), the data, and the
# headers, static libraries and CMake package for find_package(rotleak). Its Depends come from
# dpkg-shlibdeps (the shared libraries the binary and the module link) plus Python and its modules.
execute_process(COMMAND git describe --tags --match "v[0-9]*" --always --dirty WORKING_DIRECTORY ${CMAKE_SOURCE_DIR}
                OUTPUT_VARIABLE rotleak_describe OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
set(rotleak_deb_version ${PROJECT_VERSION})
if(rotleak_describe MATCHES "^v[0-9.]+-([0-9]+)-g([0-9a-f]+)")
  set(rotleak_deb_version "${PROJECT_VERSION}+${CMAKE_MATCH_1}.g${CMAKE_MATCH_2}")
elseif(rotleak_describe MATCHES "^([0-9a-f]+)")
  set(rotleak_deb_version "${PROJECT_VERSION}+g${CMAKE_MATCH_1}")
endif()
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME rotleak)
set(CPACK_PACKAGE_VERSION ${rotleak_deb_version})
set(CPACK_PACKAGE_VENDOR "the rotleak developers")
set(CPACK_PACKAGE_CONTACT "the rotleak developers <rotleak@users.noreply.invalid>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Escape from the stadium billiard with a rotating leak, with audited precision")
set(CPACK_PACKAGE_DESCRIPTION "rotleak simulates the open Bunimovich stadium with a leak rotating around its boundary
(survival probability P(t), its exponential rate and algebraic tail), audits which digits are true by
re-running trajectories at higher precision (MPFR, double-double, __float128, intervals), and analyses
the leak's speed exactly (continued fractions, the MUPO covering). Command line, Python package
(readers, plots, in-process runs) and C++ libraries (find_package(rotleak)).")
set(CPACK_RESOURCE_FILE_LICENSE ${CMAKE_SOURCE_DIR}/LICENSE)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "python3 (>= 3.11), python3-numpy, python3-pandas, python3-matplotlib")
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "libgmp-dev, libmpfr-dev, libmpfi-dev, libqd-dev, libboost-dev, libsleef-dev, libtomlplusplus-dev, librandom123-dev, nlohmann-json3-dev")
if(ROTLEAK_HAVE_PYTHON_MODULE)
  # the module is built for one Python minor version
  string(REGEX MATCH "^[0-9]+\\.[0-9]+" py_minor "${Python3_VERSION}")
  math(EXPR py_next "${Python3_VERSION_MINOR} + 1")
  set(CPACK_DEBIAN_PACKAGE_DEPENDS "python3 (>= ${py_minor}), python3 (<< ${Python3_VERSION_MAJOR}.${py_next}), python3-numpy, python3-pandas, python3-matplotlib")
endif()
# cpack (and make install) package what is built, without building first: the suite runs cpack
# (ctest Package.DebBuildsExtractsAndRuns) beside tests that use the build's binaries, and a build
# started under them would relink what they run. Build, then install or package.
set(CMAKE_SKIP_INSTALL_ALL_DEPENDENCY TRUE)
set(ROTLEAK_VERSION_HPP ${CMAKE_BINARY_DIR}/src/generated/version.hpp)  # src/CMakeLists.txt writes it
configure_file(${CMAKE_SOURCE_DIR}/cmake/cpack_project.cmake.in ${CMAKE_BINARY_DIR}/cpack_project.cmake @ONLY)
set(CPACK_PROJECT_CONFIG_FILE ${CMAKE_BINARY_DIR}/cpack_project.cmake)
include(CPack)
