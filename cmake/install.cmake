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

# headers keep the paths the sources include them by ("sim/engine.hpp", "analysis/fits.hpp")
install(DIRECTORY ${CMAKE_SOURCE_DIR}/src/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/rotleak
        FILES_MATCHING PATTERN "*.hpp" PATTERN "*.ipp" PATTERN "cli" EXCLUDE)
foreach(layer analysis verify)
  install(DIRECTORY ${CMAKE_SOURCE_DIR}/${layer}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/rotleak/${layer}
          FILES_MATCHING PATTERN "*.hpp" PATTERN "*.ipp")
endforeach()
install(FILES ${CMAKE_BINARY_DIR}/src/generated/version.hpp DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/rotleak)

install(EXPORT rotleakTargets NAMESPACE rotleak:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/rotleak)
configure_package_config_file(${CMAKE_SOURCE_DIR}/cmake/rotleakConfig.cmake.in
                              ${CMAKE_BINARY_DIR}/rotleakConfig.cmake
                              INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/rotleak)
write_basic_package_version_file(${CMAKE_BINARY_DIR}/rotleakConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/rotleakConfig.cmake ${CMAKE_BINARY_DIR}/rotleakConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/rotleak)

# the data the commands read: scenes, the study's inputs, the published tables, the reference trajectories
install(DIRECTORY ${CMAKE_SOURCE_DIR}/data/ DESTINATION ${CMAKE_INSTALL_DATADIR}/rotleak/data)
install(FILES ${CMAKE_SOURCE_DIR}/README.md ${CMAKE_SOURCE_DIR}/LICENSE ${CMAKE_SOURCE_DIR}/CITATION.cff
        DESTINATION ${CMAKE_INSTALL_DOCDIR})
