# One library per concept: src/<name>/*.cpp with public headers in include/seqtopo/<name>/ (header-only when
# the folder has no sources), exported as seqtopo::<name>.
#
# A module is built only when every target in DEPS exists: the seqtopo::<x> modules it needs, built earlier,
# and the third-party targets found by the top-level CMakeLists.txt. Otherwise it is skipped with one status
# line, and so is every module that needs it; the alignment engine, for one, needs only the standard library.
# DEPS are PUBLIC (the module's headers include them: its users compile against them), PRIVATE ones only its
# sources use (a static library still names them in its link interface, so the package looks both up).
# OPTIONAL targets are linked when they exist, and the module's own sources then see SEQTOPO_HAVE_<NAME>
# (e.g. seqtopo::recording -> SEQTOPO_HAVE_RECORDING). Each module's third-party targets are recorded for the
# package config, which finds exactly those of the modules installed (cmake/SeqtopoPackage.cmake).
include(GNUInstallDirs)
set(SEQTOPO_MODULES "" CACHE STRING "The modules to build (a ;-list, with what they need; empty: every module)")

function(seqtopo_add_module name)
  cmake_parse_arguments(M "" "" "DEPS;PRIVATE;OPTIONAL" ${ARGN})
  # SEQTOPO_MODULES (a list; empty: all) builds only the modules named and the vocabulary (core): a project that
  # needs one module does not compile the others.
  if(SEQTOPO_MODULES AND NOT name STREQUAL "core" AND NOT name IN_LIST SEQTOPO_MODULES)
    message(STATUS "seqtopo: module ${name} not built (not in SEQTOPO_MODULES)")
    return()
  endif()
  set(missing)
  foreach(dep IN LISTS M_DEPS M_PRIVATE)
    if(NOT TARGET ${dep})
      list(APPEND missing ${dep})
    endif()
  endforeach()
  if(missing)
    message(STATUS "seqtopo: module ${name} not built (missing ${missing})")
    return()
  endif()
  file(GLOB sources CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/${name}/*.cpp)
  if(sources)
    add_library(seqtopo_${name} STATIC ${sources})
    set(scope PUBLIC)
    # The project's warnings and floating-point flags apply to its own sources, not to its users'.
    target_link_libraries(seqtopo_${name} PRIVATE $<BUILD_INTERFACE:seqtopo_options>)
  else()
    add_library(seqtopo_${name} INTERFACE)
    set(scope INTERFACE)
  endif()
  add_library(seqtopo::${name} ALIAS seqtopo_${name})
  set_target_properties(seqtopo_${name} PROPERTIES EXPORT_NAME ${name})
  target_include_directories(seqtopo_${name} ${scope} $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>
                                                      $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  if(NOT name STREQUAL "core")
    target_link_libraries(seqtopo_${name} ${scope} seqtopo_core)  # every module may use the vocabulary
  endif()
  target_link_libraries(seqtopo_${name} ${scope} ${M_DEPS})
  if(M_PRIVATE)
    if(NOT sources)
      message(FATAL_ERROR "seqtopo: header-only module ${name} cannot have PRIVATE dependencies")
    endif()
    target_link_libraries(seqtopo_${name} PRIVATE ${M_PRIVATE})
  endif()
  set(third_party)
  foreach(dep IN LISTS M_DEPS M_PRIVATE)
    if(NOT dep MATCHES "^seqtopo::")
      list(APPEND third_party ${dep})
    endif()
  endforeach()
  foreach(dep IN LISTS M_OPTIONAL)
    if(TARGET ${dep})
      target_link_libraries(seqtopo_${name} ${scope} ${dep})
      string(REGEX REPLACE "^.*::" "" dep_name ${dep})
      string(TOUPPER ${dep_name} dep_name)
      if(sources)
        target_compile_definitions(seqtopo_${name} PRIVATE SEQTOPO_HAVE_${dep_name}=1)
      endif()
    endif()
  endforeach()
  install(TARGETS seqtopo_${name} EXPORT seqtopoTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/seqtopo/${name} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/seqtopo)
  set_property(GLOBAL APPEND PROPERTY SEQTOPO_MODULES seqtopo_${name})
  set_property(GLOBAL APPEND PROPERTY SEQTOPO_MODULE_NAMES ${name})
  set_property(GLOBAL PROPERTY SEQTOPO_THIRD_PARTY_${name} ${third_party})
endfunction()

# Every tests/<module>/test_*.cpp is one GoogleTest executable linked to its module and to LIBS.
function(seqtopo_add_tests module)
  cmake_parse_arguments(T "" "" "LIBS" ${ARGN})
  if(TARGET seqtopo_${module})
    list(PREPEND T_LIBS seqtopo_${module})
  endif()
  file(GLOB tests CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/${module}/test_*.cpp)
  foreach(test_source IN LISTS tests)
    get_filename_component(test_name ${test_source} NAME_WE)
    set(target ${module}_${test_name})
    add_executable(${target} ${test_source})
    target_include_directories(${target} PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
    target_link_libraries(${target} PRIVATE seqtopo_options ${T_LIBS} GTest::gtest GTest::gmock GTest::gtest_main)
    target_compile_definitions(${target} PRIVATE
      SEQTOPO_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
      SEQTOPO_SHARED_DATA_DIR="${PROJECT_SOURCE_DIR}/../shared/data"
      SEQTOPO_CLI="$<TARGET_FILE:seqtopo>")
    if(module STREQUAL "cli")
      add_dependencies(${target} seqtopo)  # these tests run the command-line tool
    endif()
    gtest_discover_tests(${target} DISCOVERY_TIMEOUT 60 PROPERTIES LABELS ${module})
  endforeach()
endfunction()
