# Small helpers so that each folder's CMakeLists.txt stays a few lines.

# srics_add_test(NAME name SOURCES a.cc b.cc LIBS lib... [LABELS slow ...] [TIMEOUT s])
# One GoogleTest executable; each TEST becomes its own ctest entry carrying LABELS.
function(srics_add_test)
  cmake_parse_arguments(T "" "NAME;TIMEOUT" "SOURCES;LIBS;LABELS" ${ARGN})
  if(NOT T_TIMEOUT)
    set(T_TIMEOUT 120)
  endif()
  if(SRICS_SANITIZE)
    # instrumented code at -O1 runs a few times slower
    math(EXPR T_TIMEOUT "${T_TIMEOUT} * 4")
  endif()
  add_executable(${T_NAME} ${T_SOURCES})
  target_link_libraries(${T_NAME} PRIVATE ${T_LIBS} GTest::gtest GTest::gtest_main Threads::Threads)
  target_compile_definitions(${T_NAME} PRIVATE
    SRICS_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    SRICS_BINARY_DIR="${PROJECT_BINARY_DIR}")
  # gtest_discover_tests writes properties unquoted, so a label list would keep only its
  # first label: join them into one ("integration-slow"), which `ctest -L slow` and
  # `ctest -L integration` both match (labels are regular expressions there)
  string(JOIN "-" joined_labels ${T_LABELS})
  # every unit test is a dependency of one target, so `cmake --build --target srics_unit_tests`
  # builds what `ctest -L unit` runs and nothing else (./tests/sanitize.sh --unit)
  if("unit" IN_LIST T_LABELS)
    add_dependencies(srics_unit_tests ${T_NAME})
  endif()
  gtest_discover_tests(${T_NAME}
    DISCOVERY_TIMEOUT 60
    PROPERTIES LABELS "${joined_labels}" TIMEOUT ${T_TIMEOUT})
endfunction()
