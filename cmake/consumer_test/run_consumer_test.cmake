# ctest install:consumer-project (registered in cmake/OrthosonarInstall.cmake), run as
#   cmake -DBUILD_DIR=... -DWORK_DIR=... -DSOURCE_DIR=... [compiler and flags] -P this file
# 1. `cmake --install BUILD_DIR --prefix WORK_DIR/prefix`
# 2. configure SOURCE_DIR (a separate project: find_package(orthosonar REQUIRED)) against
#    that prefix only, with the compiler and flags of the build under test (sanitizer
#    builds need the same runtime), build it and run it.
# Any failing step fails the test, naming the step; its output is printed.
cmake_minimum_required(VERSION 3.22)
foreach(v BUILD_DIR WORK_DIR SOURCE_DIR)
  if(NOT ${v})
    message(FATAL_ERROR "run_consumer_test.cmake: ${v} is not set")
  endif()
endforeach()

set(prefix ${WORK_DIR}/prefix)
set(consumer_build ${WORK_DIR}/build)
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})

function(step name)
  message(STATUS "consumer test: ${name}: ${ARGN}")
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  message("${out}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "consumer test: step '${name}' failed (${rc})")
  endif()
  set(step_output "${out}" PARENT_SCOPE)
endfunction()

step(install ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
foreach(f
    lib/cmake/orthosonar/orthosonarConfig.cmake
    lib/cmake/orthosonar/orthosonarTargets.cmake
    include/orthosonar/version.hpp
    include/orthosonar/replay/fixture/fixture.hpp
    include/orthosonar/core/events.hpp
    bin/orthosonar)
  if(NOT EXISTS ${prefix}/${f})
    message(FATAL_ERROR "consumer test: ${prefix}/${f} was not installed")
  endif()
endforeach()

set(configure_args -S ${SOURCE_DIR} -B ${consumer_build}
  -DCMAKE_PREFIX_PATH=${prefix}
  -DCMAKE_FIND_PACKAGE_NO_PACKAGE_REGISTRY=ON
  -DCMAKE_BUILD_TYPE=${BUILD_TYPE})
if(GENERATOR)
  list(APPEND configure_args -G ${GENERATOR})
endif()
if(CXX_COMPILER)
  list(APPEND configure_args -DCMAKE_CXX_COMPILER=${CXX_COMPILER})
endif()
if(C_COMPILER)
  list(APPEND configure_args -DCMAKE_C_COMPILER=${C_COMPILER})
endif()
if(BUILD_TYPE)
  string(TOUPPER "${BUILD_TYPE}" config)
  list(APPEND configure_args "-DCMAKE_CXX_FLAGS_${config}=${CXX_FLAGS_CONFIG}" "-DCMAKE_C_FLAGS_${config}=${C_FLAGS_CONFIG}")
endif()
list(APPEND configure_args "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}" "-DCMAKE_C_FLAGS=${C_FLAGS}"
  "-DCMAKE_EXE_LINKER_FLAGS=${EXE_LINKER_FLAGS}")
step(configure ${CMAKE_COMMAND} ${configure_args})
step(build ${CMAKE_COMMAND} --build ${consumer_build})
step(run ${consumer_build}/orthosonar_consumer ${WORK_DIR})
if(NOT step_output MATCHES "consumer: ok")
  message(FATAL_ERROR "consumer test: the program did not report 'consumer: ok'")
endif()
step(cli ${prefix}/bin/orthosonar --version)
message(STATUS "consumer test: passed")
