# `cmake --install` gives find_package(seqtopo CONFIG [COMPONENTS ...]): one imported target per module
# that was built (seqtopo::align, seqtopo::mapping, ...) and the umbrella seqtopo::seqtopo linking them all.
include(CMakePackageConfigHelpers)

get_property(seqtopo_built_modules GLOBAL PROPERTY SEQTOPO_MODULES)
get_property(SEQTOPO_INSTALLED_MODULES GLOBAL PROPERTY SEQTOPO_MODULE_NAMES)
add_library(seqtopo_all INTERFACE)
set_target_properties(seqtopo_all PROPERTIES EXPORT_NAME seqtopo)
target_link_libraries(seqtopo_all INTERFACE ${seqtopo_built_modules})
add_library(seqtopo::seqtopo ALIAS seqtopo_all)
install(TARGETS seqtopo_all EXPORT seqtopoTargets)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/seqtopo/core DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/seqtopo)

set(SEQTOPO_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/seqtopo)
install(EXPORT seqtopoTargets NAMESPACE seqtopo:: DESTINATION ${SEQTOPO_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/seqtopoConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/seqtopoConfig.cmake INSTALL_DESTINATION ${SEQTOPO_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/seqtopoConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/seqtopoConfig.cmake ${PROJECT_BINARY_DIR}/seqtopoConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/cmake/SeqtopoRecordingDeps.cmake DESTINATION ${SEQTOPO_CMAKE_DIR})
