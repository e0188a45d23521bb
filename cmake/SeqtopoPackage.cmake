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

# The config finds the third-party packages of the modules installed, derived from what each module links
# (seqtopo_add_module records them): a target without a line here stops the configuration, so the list cannot
# fall behind the modules.
set(seqtopo_package_of_Threads::Threads "find_dependency(Threads)")
set(seqtopo_package_of_OpenMP::OpenMP_CXX "find_dependency(OpenMP)")
set(seqtopo_package_of_fmt::fmt "find_dependency(fmt)")
set(seqtopo_package_of_nlohmann_json::nlohmann_json "find_dependency(nlohmann_json)")
set(seqtopo_package_of_Eigen3::Eigen "find_dependency(Eigen3 NO_MODULE)")
set(seqtopo_package_of_Ceres::ceres "find_dependency(Ceres)")
set(seqtopo_package_of_OpenSSL::Crypto "find_dependency(OpenSSL COMPONENTS Crypto)")
set(seqtopo_package_of_PNG::PNG "find_dependency(PNG)")
set(seqtopo_package_of_JPEG::JPEG "find_dependency(JPEG)")
foreach(opencv opencv_core opencv_imgproc)
  set(seqtopo_package_of_${opencv} "find_dependency(OpenCV COMPONENTS core imgproc imgcodecs videoio)")
endforeach()
set(seqtopo_faiss_lookup [[
if(NOT TARGET faiss)
  find_package(faiss QUIET)
  if(NOT TARGET faiss)
    # Debian's FAISS ships no CMake config: the same imported target the build used.
    find_library(seqtopo_FAISS_LIBRARY faiss REQUIRED)
    find_path(seqtopo_FAISS_INCLUDE_DIR faiss/IndexFlat.h REQUIRED)
    add_library(faiss INTERFACE IMPORTED)
    target_link_libraries(faiss INTERFACE ${seqtopo_FAISS_LIBRARY} OpenMP::OpenMP_CXX)
    target_include_directories(faiss SYSTEM INTERFACE ${seqtopo_FAISS_INCLUDE_DIR})
  endif()
endif()]])
set(seqtopo_package_of_faiss "${seqtopo_faiss_lookup}")
# The recording module's libraries are found by the file its build used.
foreach(recording seqtopo_ros1 SQLite::SQLite3 seqtopo_zstd seqtopo_lz4 seqtopo_yaml ZLIB::ZLIB)
  set(seqtopo_package_of_${recording} [[include("${CMAKE_CURRENT_LIST_DIR}/SeqtopoRecordingDeps.cmake")]])
endforeach()
set(SEQTOPO_FIND_DEPENDENCIES)
foreach(module IN LISTS SEQTOPO_INSTALLED_MODULES)
  get_property(third_party GLOBAL PROPERTY SEQTOPO_THIRD_PARTY_${module})
  foreach(target IN LISTS third_party)
    if(NOT DEFINED seqtopo_package_of_${target})
      message(FATAL_ERROR "seqtopo: module ${module} links ${target}: say in cmake/SeqtopoPackage.cmake how its "
                          "package is found")
    endif()
    set(line "${seqtopo_package_of_${target}}")
    # OpenMP before FAISS, whose imported target links it.
    if(target STREQUAL "faiss")
      list(APPEND faiss_lines "${line}")
    elseif(NOT "${line}" IN_LIST SEQTOPO_FIND_DEPENDENCIES)
      list(APPEND SEQTOPO_FIND_DEPENDENCIES "${line}")
    endif()
  endforeach()
endforeach()
if(faiss_lines)
  list(APPEND SEQTOPO_FIND_DEPENDENCIES "find_dependency(OpenMP)" "${seqtopo_faiss_lookup}")
  list(REMOVE_DUPLICATES SEQTOPO_FIND_DEPENDENCIES)
endif()
list(JOIN SEQTOPO_FIND_DEPENDENCIES "\n" SEQTOPO_FIND_DEPENDENCIES)

set(SEQTOPO_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/seqtopo)
install(EXPORT seqtopoTargets NAMESPACE seqtopo:: DESTINATION ${SEQTOPO_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/seqtopoConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/seqtopoConfig.cmake INSTALL_DESTINATION ${SEQTOPO_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/seqtopoConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/seqtopoConfig.cmake ${PROJECT_BINARY_DIR}/seqtopoConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/cmake/SeqtopoRecordingDeps.cmake DESTINATION ${SEQTOPO_CMAKE_DIR})
