# One helper for every folder: warnings on our code only, sources found by convention.
#   <stage>.cpp / <stage>.hpp     library sources
#   <stage>_test.cpp              Catch2 tests, linked into <target>_tests and registered with ctest
#   <stage>_bench.cpp             Google Benchmark cases, linked into the one orthosonar_bench
# New files are picked up on the next build (CONFIGURE_DEPENDS).

function(orthosonar_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wconversion -Werror
    -Wno-error=deprecated-declarations)
  # The reference build (SPEC §9): no FMA contraction, no fast-math, no -march=native.
  target_compile_options(${target} PRIVATE -ffp-contract=off)
endfunction()

set_property(GLOBAL PROPERTY ORTHOSONAR_BENCH_SOURCES "")
set_property(GLOBAL PROPERTY ORTHOSONAR_BENCH_LIBS "")

# orthosonar_module(<target> [DIR dir] LIBS <public deps...> [TEST_LIBS ...] [LABELS ...])
function(orthosonar_module target)
  cmake_parse_arguments(M "" "DIR" "LIBS;PRIVATE_LIBS;TEST_LIBS;LABELS" ${ARGN})
  if(NOT M_DIR)
    set(M_DIR ${CMAKE_CURRENT_SOURCE_DIR})
  endif()
  if(NOT M_LABELS)
    set(M_LABELS unit)
  endif()
  file(GLOB all_cpp CONFIGURE_DEPENDS ${M_DIR}/*.cpp)
  set(lib_src "")
  set(test_src "")
  set(bench_src "")
  foreach(f ${all_cpp})
    if(f MATCHES "_test\\.cpp$")
      list(APPEND test_src ${f})
    elseif(f MATCHES "_bench\\.cpp$")
      list(APPEND bench_src ${f})
    else()
      list(APPEND lib_src ${f})
    endif()
  endforeach()
  if(lib_src)
    add_library(${target} STATIC ${lib_src})
  else()
    add_library(${target} INTERFACE)
  endif()
  get_target_property(kind ${target} TYPE)
  if(kind STREQUAL "INTERFACE_LIBRARY")
    target_include_directories(${target} INTERFACE ${PROJECT_SOURCE_DIR} ${CMAKE_BINARY_DIR}/generated)
    target_link_libraries(${target} INTERFACE ${M_LIBS})
  else()
    target_include_directories(${target} PUBLIC ${PROJECT_SOURCE_DIR} ${CMAKE_BINARY_DIR}/generated)
    target_link_libraries(${target} PUBLIC ${M_LIBS} PRIVATE ${M_PRIVATE_LIBS})
    orthosonar_warnings(${target})
  endif()
  if(ORTHOSONAR_BUILD_TESTS AND test_src)
    add_executable(${target}_tests ${test_src})
    target_link_libraries(${target}_tests PRIVATE ${target} ${M_TEST_LIBS} orthosonar_test_main)
    orthosonar_warnings(${target}_tests)
    catch_discover_tests(${target}_tests
      TEST_PREFIX "${target}:"
      PROPERTIES LABELS "${M_LABELS}")  # environment: see property_tests/catch_main.cpp
  endif()
  if(bench_src)
    set_property(GLOBAL APPEND PROPERTY ORTHOSONAR_BENCH_SOURCES ${bench_src})
    set_property(GLOBAL APPEND PROPERTY ORTHOSONAR_BENCH_LIBS ${target})
  endif()
endfunction()

function(orthosonar_finish_bench)
  get_property(srcs GLOBAL PROPERTY ORTHOSONAR_BENCH_SOURCES)
  get_property(libs GLOBAL PROPERTY ORTHOSONAR_BENCH_LIBS)
  add_executable(orthosonar_bench ${PROJECT_SOURCE_DIR}/tools/bench_main.cpp ${srcs})
  target_link_libraries(orthosonar_bench PRIVATE ${libs} benchmark::benchmark)
  orthosonar_warnings(orthosonar_bench)
endfunction()

# Every orthosonar library target that exists (tools, golden and property tests link them all).
function(orthosonar_all_libraries out_var)
  set(libs "")
  foreach(t orthosonar_core orthosonar_perception orthosonar_slam orthosonar_mapping orthosonar_inference
      orthosonar_hal orthosonar_sim orthosonar_drivers orthosonar_replay orthosonar_outputs orthosonar_reports)
    if(TARGET ${t})
      list(APPEND libs ${t})
    endif()
  endforeach()
  set(${out_var} ${libs} PARENT_SCOPE)
endfunction()
