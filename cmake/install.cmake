# Installation under the GNU install dirs:
#   bin/chainmail
#   share/chainmail/{scenes/, shaders/, report/, plot_sweep.py, scene.schema.json}  (read at run time,
#                                                        found from the binary's own path)
#   include/chainmail/{core/, backends/, scene_file/{scene_file,strict_json}.hpp, testing/}
#   lib/libchainmail_*.a and lib/cmake/chainmail/ (find_package(chainmail))
#   share/doc/chainmail/ (README, LICENSE, CITATION.cff, docs/)
include(CMakePackageConfigHelpers)

set(CHAINMAIL_INSTALL_DATADIR ${CMAKE_INSTALL_DATADIR}/chainmail)
set(chainmail_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/chainmail)

# the libraries outside code builds a backend on, as chainmail::<name>
set(chainmail_libraries chainmail_core chainmail_capsule_torus chainmail_backends
  chainmail_scene_file)
set_target_properties(chainmail_core PROPERTIES EXPORT_NAME core)
set_target_properties(chainmail_capsule_torus PROPERTIES EXPORT_NAME capsule_torus)
set_target_properties(chainmail_backends PROPERTIES EXPORT_NAME backends)
set_target_properties(chainmail_scene_file PROPERTIES EXPORT_NAME scene_file)
foreach(optional bullet ode)
  if(TARGET chainmail_backend_${optional})
    list(APPEND chainmail_libraries chainmail_backend_${optional})
    set_target_properties(chainmail_backend_${optional} PROPERTIES
      EXPORT_NAME backend_${optional})
  endif()
endforeach()

install(TARGETS chainmail RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS ${chainmail_libraries} EXPORT chainmailTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})

# headers keep their source paths under include/chainmail/, which is on the include path too, so
# that the installed headers' own includes ("core/scene.hpp") resolve
set(chainmail_include ${CMAKE_INSTALL_INCLUDEDIR}/chainmail)
install(DIRECTORY core/ DESTINATION ${chainmail_include}/core FILES_MATCHING PATTERN "*.hpp")
install(FILES backends/backend.hpp backends/knobs.hpp backends/capsule_torus.hpp DESTINATION ${chainmail_include}/backends)
install(FILES scene_file/scene_file.hpp scene_file/strict_json.hpp DESTINATION ${chainmail_include}/scene_file)
install(FILES tests/backends/backend_contract.hpp tests/backends/backend_sim.hpp
              tests/backends/collider_cases.hpp
        DESTINATION ${chainmail_include}/testing)

install(DIRECTORY shaders bench/scenes report DESTINATION ${CHAINMAIL_INSTALL_DATADIR})
if(CHAINMAIL_THREE_JS)
  install(FILES ${CHAINMAIL_THREE_JS} DESTINATION ${CHAINMAIL_INSTALL_DATADIR}/report)
endif()
install(FILES bench/plot_sweep.py bench/plot_scaling.py docs/scene.schema.json DESTINATION ${CHAINMAIL_INSTALL_DATADIR})
install(FILES README.md LICENSE CITATION.cff DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR}/docs)

install(EXPORT chainmailTargets NAMESPACE chainmail:: DESTINATION ${chainmail_cmake_dir})
configure_package_config_file(cmake/chainmailConfig.cmake.in
  ${PROJECT_BINARY_DIR}/chainmailConfig.cmake
  INSTALL_DESTINATION ${chainmail_cmake_dir}
  PATH_VARS CHAINMAIL_INSTALL_DATADIR)
# 0.x: a minor version may change the interface
write_basic_package_version_file(${PROJECT_BINARY_DIR}/chainmailConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/chainmailConfig.cmake
              ${PROJECT_BINARY_DIR}/chainmailConfigVersion.cmake
        DESTINATION ${chainmail_cmake_dir})
