# `cmake --install`: the orthosonar libraries (static), their public headers, the generated
# orthosonar/version.hpp, the `orthosonar` CLI and a CMake package, so that another project
# can write
#   find_package(orthosonar REQUIRED)
#   target_link_libraries(app PRIVATE orthosonar::replay)
# Libraries are added to the export set by orthosonar_module() (cmake/OrthosonarModule.cmake);
# this file is included once, after every module exists.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(ORTHOSONAR_CMAKE_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/orthosonar)

install(FILES ${CMAKE_BINARY_DIR}/generated/orthosonar/version.hpp
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/orthosonar)
if(TARGET orthosonar)
  install(TARGETS orthosonar RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()

install(EXPORT orthosonarTargets
  NAMESPACE orthosonar::
  FILE orthosonarTargets.cmake
  DESTINATION ${ORTHOSONAR_CMAKE_INSTALL_DIR})

get_property(ORTHOSONAR_INSTALLED_MODULES GLOBAL PROPERTY ORTHOSONAR_INSTALLED_MODULES)
string(REPLACE "orthosonar_" "" ORTHOSONAR_EXPORTED_COMPONENTS "${ORTHOSONAR_INSTALLED_MODULES}")
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/orthosonarConfig.cmake.in
  ${CMAKE_BINARY_DIR}/package/orthosonarConfig.cmake
  INSTALL_DESTINATION ${ORTHOSONAR_CMAKE_INSTALL_DIR})
# 0.x: a minor version may break the API.
write_basic_package_version_file(${CMAKE_BINARY_DIR}/package/orthosonarConfigVersion.cmake
  VERSION ${PROJECT_VERSION}
  COMPATIBILITY SameMinorVersion)
install(FILES
  ${CMAKE_BINARY_DIR}/package/orthosonarConfig.cmake
  ${CMAKE_BINARY_DIR}/package/orthosonarConfigVersion.cmake
  DESTINATION ${ORTHOSONAR_CMAKE_INSTALL_DIR})

# The package works from another project: install this build into a prefix under the
# build tree, then configure, build and run cmake/consumer_test against it (a fixture
# written and read back through orthosonar::replay, and more, see its main.cpp). Nothing
# of orthosonar is recompiled; the consumer is one translation unit.
if(ORTHOSONAR_BUILD_TESTS)
  string(TOUPPER "${CMAKE_BUILD_TYPE}" _orthosonar_build_type_upper)
  add_test(NAME install:consumer-project
    COMMAND ${CMAKE_COMMAND}
      -DBUILD_DIR=${CMAKE_BINARY_DIR}
      -DWORK_DIR=${CMAKE_BINARY_DIR}/test_out/install_consumer
      -DSOURCE_DIR=${CMAKE_CURRENT_LIST_DIR}/consumer_test
      -DGENERATOR=${CMAKE_GENERATOR}
      -DCXX_COMPILER=${CMAKE_CXX_COMPILER}
      -DC_COMPILER=${CMAKE_C_COMPILER}
      -DBUILD_TYPE=${CMAKE_BUILD_TYPE}
      "-DCXX_FLAGS=${CMAKE_CXX_FLAGS}"
      "-DCXX_FLAGS_CONFIG=${CMAKE_CXX_FLAGS_${_orthosonar_build_type_upper}}"
      "-DC_FLAGS=${CMAKE_C_FLAGS}"
      "-DC_FLAGS_CONFIG=${CMAKE_C_FLAGS_${_orthosonar_build_type_upper}}"
      "-DEXE_LINKER_FLAGS=${CMAKE_EXE_LINKER_FLAGS}"
      -P ${CMAKE_CURRENT_LIST_DIR}/consumer_test/run_consumer_test.cmake)
  set_tests_properties(install:consumer-project PROPERTIES LABELS unit TIMEOUT 600)
endif()
