# `cmake --install`: the exoid binary, the libraries with their public headers, the run-time data
# (share/exoid) and a CMake package (find_package(exoid) -> exoid::ident, exoid::sim, ...).
include(CMakePackageConfigHelpers)
set(EXOID_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/exoid)

set(_exoid_libs exoid_core exoid_ident exoid_experiments_common exoid_experiments exoid_warnings)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/core/include/ ${PROJECT_SOURCE_DIR}/ident/include/ ${PROJECT_SOURCE_DIR}/experiments/include/
        ${PROJECT_BINARY_DIR}/experiments/generated/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
if(TARGET exoid_sim)
  list(APPEND _exoid_libs exoid_sim)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/sim/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endif()
if(TARGET exoid_render)
  list(APPEND _exoid_libs exoid_render)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/render/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endif()
foreach(_lib IN LISTS _exoid_libs)
  if(NOT _lib STREQUAL "exoid_warnings")
    get_target_property(_dirs ${_lib} INTERFACE_INCLUDE_DIRECTORIES)
    set(_build_dirs)
    foreach(_d IN LISTS _dirs)
      list(APPEND _build_dirs "$<BUILD_INTERFACE:${_d}>")
    endforeach()
    set_target_properties(${_lib} PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${_build_dirs}")
    target_include_directories(${_lib} INTERFACE $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  endif()
  string(REPLACE "exoid_" "" _short ${_lib})
  set_target_properties(${_lib} PROPERTIES EXPORT_NAME ${_short})
endforeach()
install(TARGETS ${_exoid_libs} EXPORT exoidTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS exoid RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
if(TARGET exoid-full)  # `exoid` looks for it in ../libexec (commands/launcher.hpp); its data is ../share/exoid from there too
  install(TARGETS exoid-full RUNTIME DESTINATION ${CMAKE_INSTALL_LIBEXECDIR})
endif()
install(EXPORT exoidTargets NAMESPACE exoid:: DESTINATION ${EXOID_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/exoidConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/exoidConfig.cmake INSTALL_DESTINATION ${EXOID_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/exoidConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/exoidConfig.cmake ${PROJECT_BINARY_DIR}/exoidConfigVersion.cmake
        DESTINATION ${EXOID_CMAKE_DIR})

install(DIRECTORY ${PROJECT_SOURCE_DIR}/models/ DESTINATION ${CMAKE_INSTALL_DATADIR}/exoid/models)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/experiments/plots/ DESTINATION ${CMAKE_INSTALL_DATADIR}/exoid/plots)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/experiments/configs/ DESTINATION ${CMAKE_INSTALL_DATADIR}/exoid/configs)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/data/ DESTINATION ${CMAKE_INSTALL_DATADIR}/exoid/data)
