# Packaging tests: an installed isoforge used by a separate project, and installed programs run
# from a moved install prefix.
#
# consumer_package: install this build (shared or static, as configured) into a scratch prefix,
# then configure, build and run the separate project in tests/consumer/ against it with
# find_package(isoforge), including the C++ example of the README.
get_target_property(_isoforge_type isoforge_base TYPE)
set(_consumer_args
  -DSOURCE_DIR=${CMAKE_CURRENT_SOURCE_DIR}/consumer
  -DDATA_FILE=${PROJECT_SOURCE_DIR}/data/hello.vtk
  -DDATA_DIR=${PROJECT_SOURCE_DIR}/data
  -DGENERATOR=${CMAKE_GENERATOR}
  -DCXX=${CMAKE_CXX_COMPILER})
add_test(NAME consumer_package
  COMMAND ${CMAKE_COMMAND} ${_consumer_args}
    -DBUILD_DIR=${PROJECT_BINARY_DIR}
    -DWORK_DIR=${CMAKE_CURRENT_BINARY_DIR}/consumer
    -DLIBRARY_TYPE=${_isoforge_type}
    -P ${CMAKE_CURRENT_SOURCE_DIR}/consumer/run_consumer.cmake)
set_tests_properties(consumer_package PROPERTIES LABELS consumer TIMEOUT 600)

# consumer_package_static (in shared builds; a static build's consumer_package is that test):
# the same against a static isoforge, configured as a second, library-only build of these sources
# with BUILD_SHARED_LIBS=OFF and installed with the Development component. That build lives
# beside this one (<build>-consumer-static), and the library's compile commands name no build
# directory (src/CMakeLists.txt), so they are identical to this build's; ccache, with or without
# a base_dir, then serves every object and the test takes seconds instead of a library build.
if(_isoforge_type STREQUAL "SHARED_LIBRARY")
  add_test(NAME consumer_package_static
    COMMAND ${CMAKE_COMMAND} ${_consumer_args}
      -DISOFORGE_SOURCE_DIR=${PROJECT_SOURCE_DIR}
      -DSTATIC_BUILD_DIR=${PROJECT_BINARY_DIR}-consumer-static
      -DBUILD_TYPE=$<CONFIG>
      -DX86_64_V2=${ISOFORGE_X86_64_V2}
      "-DSANITIZE=${ISOFORGE_SANITIZE}"
      "-DCXX_FLAGS=${CMAKE_CXX_FLAGS}"
      -DWORK_DIR=${CMAKE_CURRENT_BINARY_DIR}/consumer-static
      -DLIBRARY_TYPE=STATIC_LIBRARY
      -P ${CMAKE_CURRENT_SOURCE_DIR}/consumer/run_consumer.cmake)
  # A cold ccache compiles the whole library.
  set_tests_properties(consumer_package_static PROPERTIES LABELS consumer TIMEOUT 1800)
endif()

# runpath: every program and shared library of the build tree searches for libraries only in
# absolute directories or ones relative to itself, never the current directory (the root
# CMakeLists.txt, "The build tree mirrors that layout"); the checker's own test beside it.
set(_runpath_expect)
if(_isoforge_type STREQUAL "SHARED_LIBRARY")
  set(_runpath_expect --expect isoforge --expect libisoforge_vdb.so.0.1.0)
endif()
# Only where the layout is mirrored: otherwise CMake's padded build RPATH is all there is.
if(ISOFORGE_MIRRORED_RPATH)
  add_test(NAME runpath
           COMMAND Python3::Interpreter ${CMAKE_CURRENT_SOURCE_DIR}/consumer/check_runpath.py
                   ${_runpath_expect} ${PROJECT_BINARY_DIR})
  set_tests_properties(runpath PROPERTIES LABELS install)
endif()
add_test(NAME runpath_self_test
         COMMAND Python3::Interpreter ${CMAKE_CURRENT_SOURCE_DIR}/consumer/check_runpath.py
                 --self-test)
set_tests_properties(runpath_self_test PROPERTIES LABELS install)

# install_relocatable: install into a scratch prefix and run the installed programs with
# LD_LIBRARY_PATH unset, then move the prefix and run them again (relative RPATH).
add_test(NAME install_relocatable
  COMMAND ${CMAKE_COMMAND}
    -DBUILD_DIR=${PROJECT_BINARY_DIR}
    -DWORK_DIR=${CMAKE_CURRENT_BINARY_DIR}/install_relocatable
    -DDATA_DIR=${PROJECT_SOURCE_DIR}/data
    -DWITH_VERIFY=${ISOFORGE_BUILD_VERIFY}
    -DLIBRARY_TYPE=${_isoforge_type}
    -DPYTHON=$<TARGET_FILE:Python3::Interpreter>
    -P ${CMAKE_CURRENT_SOURCE_DIR}/consumer/run_install.cmake)
set_tests_properties(install_relocatable PROPERTIES LABELS install TIMEOUT 300)
