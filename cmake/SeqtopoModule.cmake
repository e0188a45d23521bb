# One static library per concept: src/<name>/*.cpp with public headers in include/seqtopo/<name>/.
# A module whose folder has no sources yet is skipped, so layers can be added one at a time.
function(seqtopo_add_module name)
  cmake_parse_arguments(M "" "" "DEPS" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/${name}/*.cpp)
  if(NOT sources)
    return()
  endif()
  add_library(seqtopo_${name} STATIC ${sources})
  add_library(seqtopo::${name} ALIAS seqtopo_${name})
  target_include_directories(seqtopo_${name} PUBLIC ${PROJECT_SOURCE_DIR}/include)
  target_link_libraries(seqtopo_${name} PUBLIC seqtopo_options ${M_DEPS})
  if(NOT name STREQUAL "core")
    target_link_libraries(seqtopo_${name} PUBLIC seqtopo_core)  # every module may use the vocabulary
  endif()
  set_property(GLOBAL APPEND PROPERTY SEQTOPO_MODULES seqtopo_${name})
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
