# One helper for every folder: warnings on our code only, sources found by convention.
#   <stage>.cpp / <stage>.hpp     library sources
#   <stage>_test.cpp              Catch2 tests, linked into <target>_tests and registered with ctest
#   <stage>_bench.cpp             Google Benchmark cases, linked into the one orthosonar_bench
#   <stage>_fuzz.cpp              a libFuzzer harness, built as fuzz_<stage> (fuzz preset only)
# New files are picked up on the next build (CONFIGURE_DEPENDS).

# Warnings are errors only where asked for: ORTHOSONAR_WERROR (default ON when the
# environment says CI=true, as our CI does; OFF for users, packagers and every preset that
# does not set it). GCC 12 reports false positives at some optimisation levels
# (-Wrestrict at -O3, -Wmaybe-uninitialized in <regex> under the sanitizers): a user's
# build must never fail on them.
if("$ENV{CI}" STREQUAL "true")
  set(_orthosonar_werror_default ON)
else()
  set(_orthosonar_werror_default OFF)
endif()
option(ORTHOSONAR_WERROR "Treat compiler warnings in orthosonar's own code as errors" ${_orthosonar_werror_default})

function(orthosonar_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wconversion)
  if(CMAKE_UNITY_BUILD AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    # In a unity batch every .cpp is an included file, so GCC reports a class of one .cpp
    # holding a type from that .cpp's anonymous namespace (Simulator::Impl, the emulator's
    # Server): correct code, and the same translation unit holds both.
    target_compile_options(${target} PRIVATE -Wno-subobject-linkage)
  endif()
  if(ORTHOSONAR_WERROR)
    target_compile_options(${target} PRIVATE -Werror -Wno-error=deprecated-declarations)
  endif()
  # The reference build (SPEC §9): no FMA contraction, no fast-math, no -march=native.
  target_compile_options(${target} PRIVATE -ffp-contract=off)
endfunction()

set_property(GLOBAL PROPERTY ORTHOSONAR_BENCH_SOURCES "")
set_property(GLOBAL PROPERTY ORTHOSONAR_BENCH_LIBS "")

include(GNUInstallDirs)

# Installs a library module and adds it to the orthosonar package (export set
# orthosonarTargets, see cmake/OrthosonarInstall.cmake): orthosonar_<name> is known as
# orthosonar::<name> both in this build (an ALIAS) and to find_package(orthosonar) users.
# Its public headers (every *.hpp in the module folder except test helpers) go to
# include/orthosonar/<folder>/, so "#include \"replay/fixture/fixture.hpp\"" works after install too.
function(orthosonar_install_module target dir)
  string(REGEX REPLACE "^orthosonar_" "" short ${target})
  add_library(orthosonar::${short} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${short})
  install(TARGETS ${target} EXPORT orthosonarTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  file(GLOB headers CONFIGURE_DEPENDS ${dir}/*.hpp)
  list(FILTER headers EXCLUDE REGEX "/(test_support|test_dir|testing|fuzz_support)\\.hpp$")
  file(RELATIVE_PATH rel ${PROJECT_SOURCE_DIR} ${dir})
  if(headers)
    install(FILES ${headers} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/orthosonar/${rel})
  endif()
  set_property(GLOBAL APPEND PROPERTY ORTHOSONAR_INSTALLED_MODULES ${target})
endfunction()

# orthosonar_module(<target> [DIR dir] LIBS <public deps...> [TEST_LIBS ...] [LABELS ...]
#                   [FUZZ_SOURCES <module sources> FUZZ_LIBS <deps>])
# A harness links the module's library, or, when FUZZ_SOURCES is given, compiles just those
# sources of the module with FUZZ_LIBS (a parser in a module whose library pulls in much more).
function(orthosonar_module target)
  cmake_parse_arguments(M "" "DIR" "LIBS;PRIVATE_LIBS;TEST_LIBS;LABELS;FUZZ_SOURCES;FUZZ_LIBS" ${ARGN})
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
  set(fuzz_src "")
  foreach(f ${all_cpp})
    if(f MATCHES "_test\\.cpp$")
      list(APPEND test_src ${f})
    elseif(f MATCHES "_bench\\.cpp$")
      list(APPEND bench_src ${f})
    elseif(f MATCHES "_fuzz\\.cpp$")
      list(APPEND fuzz_src ${f})
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
  # Headers are included as "core/...", "hal/...", "replay/..." and "orthosonar/version.hpp",
  # in the build tree and installed alike (see orthosonar_install_module).
  set(includes
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>
    $<BUILD_INTERFACE:${CMAKE_BINARY_DIR}/generated>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/orthosonar>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  if(kind STREQUAL "INTERFACE_LIBRARY")
    target_include_directories(${target} INTERFACE ${includes})
    target_link_libraries(${target} INTERFACE ${M_LIBS})
  else()
    target_include_directories(${target} PUBLIC ${includes})
    target_link_libraries(${target} PUBLIC ${M_LIBS} PRIVATE ${M_PRIVATE_LIBS})
    orthosonar_warnings(${target})
    if(ORTHOSONAR_FUZZ_COVERAGE_PER_MODULE AND fuzz_src AND NOT M_FUZZ_SOURCES)
      target_compile_options(${target} PRIVATE -fsanitize=fuzzer-no-link)  # a harness fuzzes this library
    endif()
  endif()
  if(ORTHOSONAR_SANITIZE)
    # A sanitized static library needs the sanitizer runtime wherever it is linked, including
    # by an installed consumer (find_package(orthosonar) from an asan build).
    target_link_options(${target} INTERFACE -fsanitize=${ORTHOSONAR_SANITIZE})
  endif()
  orthosonar_install_module(${target} ${M_DIR})
  if(ORTHOSONAR_BUILD_TESTS AND test_src)
    add_executable(${target}_tests ${test_src})
    target_link_libraries(${target}_tests PRIVATE ${target} ${M_TEST_LIBS} orthosonar_test_main)
    orthosonar_warnings(${target}_tests)
    catch_discover_tests(${target}_tests
      TEST_PREFIX "${target}:"
      # A ctest entry whose name matches no test case (a ';' in the name splits it) fails
      # instead of passing with nothing run.
      EXTRA_ARGS -w NoTests
      PROPERTIES LABELS "${M_LABELS}")  # environment: see property_tests/catch_main.cpp
  endif()
  if(ORTHOSONAR_BUILD_FUZZ)
    foreach(f ${fuzz_src})
      get_filename_component(stem ${f} NAME_WE)
      string(REGEX REPLACE "_fuzz$" "" stem ${stem})
      if(M_FUZZ_SOURCES)
        list(TRANSFORM M_FUZZ_SOURCES PREPEND ${M_DIR}/ OUTPUT_VARIABLE own_src)
        add_executable(fuzz_${stem} ${f} ${own_src})
        target_include_directories(fuzz_${stem} PRIVATE ${PROJECT_SOURCE_DIR} ${CMAKE_BINARY_DIR}/generated)
        target_link_libraries(fuzz_${stem} PRIVATE ${M_FUZZ_LIBS})
      else()
        add_executable(fuzz_${stem} ${f})
        target_link_libraries(fuzz_${stem} PRIVATE ${target} ${M_PRIVATE_LIBS})
      endif()
      target_link_options(fuzz_${stem} PRIVATE -fsanitize=fuzzer)
      if(ORTHOSONAR_FUZZ_COVERAGE_PER_MODULE)
        target_compile_options(fuzz_${stem} PRIVATE -fsanitize=fuzzer-no-link)
      endif()
      set_target_properties(fuzz_${stem} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/fuzz)
      orthosonar_warnings(fuzz_${stem})
      add_dependencies(fuzzers fuzz_${stem})
    endforeach()
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
  # Benchmarks on the example user scenes (docs/examples) read them from the source tree.
  target_compile_definitions(orthosonar_bench PRIVATE ORTHOSONAR_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  orthosonar_warnings(orthosonar_bench)
endfunction()

# Every orthosonar library target that exists (tools, golden and property tests link them all).
function(orthosonar_all_libraries out_var)
  set(libs "")
  foreach(t orthosonar_core orthosonar_perception orthosonar_slam orthosonar_mapping orthosonar_inference
      orthosonar_hal orthosonar_config orthosonar_codec orthosonar_sim orthosonar_drivers orthosonar_mcap
      orthosonar_ros1_codec orthosonar_fixture orthosonar_digest orthosonar_replay orthosonar_outputs
      orthosonar_reports orthosonar_run orthosonar_ros orthosonar_batch orthosonar_verify)
    if(TARGET ${t})
      list(APPEND libs ${t})
    endif()
  endforeach()
  set(${out_var} ${libs} PARENT_SCOPE)
endfunction()
