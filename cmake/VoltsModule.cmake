# volts_module(NAME SOURCES ... DEPS ...)
# Declares the library of modules/NAME: target volts_NAME, alias volts::NAME, namespace volts::NAME.
function(volts_module name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_library(volts_${name} ${ARG_SOURCES})
  add_library(volts::${name} ALIAS volts_${name})
  target_include_directories(volts_${name} PUBLIC ${PROJECT_SOURCE_DIR}/modules)
  target_link_libraries(volts_${name} PUBLIC ${ARG_DEPS})
  volts_warnings(volts_${name})
endfunction()

function(volts_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic)
  if(VOLTS_WARNINGS_AS_ERRORS)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# volts_test(NAME SOURCES ... DEPS ...): one GoogleTest executable registered with ctest; tests/ is on
# its include path for the shared helpers in tests/common.
function(volts_test name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} GTest::gtest GTest::gtest_main)
  # Shared helpers: #include "common/test_util.h" (tests/common, header-only).
  target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR}/tests)
  target_compile_definitions(${name} PRIVATE
    VOLTS_SHARED_MODELS="${PROJECT_SOURCE_DIR}/../shared/models"
    VOLTS_BINARY_DIR="${PROJECT_BINARY_DIR}")
  volts_warnings(${name})
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60)
endfunction()
