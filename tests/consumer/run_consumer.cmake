# Script of the consumer_package tests (see tests/consumer.cmake): install an isoforge build into
# a scratch prefix, then configure, build and run tests/consumer/ against it.
#
#   BUILD_DIR           the build to install (consumer_package), or
#   STATIC_BUILD_DIR    configure and build a library-only static isoforge from
#                       ISOFORGE_SOURCE_DIR there first (BUILD_TYPE, X86_64_V2, SANITIZE,
#                       CXX_FLAGS as in the calling build), and install that
#   LIBRARY_TYPE        STATIC_LIBRARY or SHARED_LIBRARY: what the prefix must hold
#   WORK_DIR            scratch directory (prefix, consumer build)
#   SOURCE_DIR DATA_FILE DATA_DIR GENERATOR CXX
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message("${out}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "command failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
endfunction()

if(STATIC_BUILD_DIR)
  # Kept between runs: a rerun is an incremental build.
  run(${CMAKE_COMMAND} -S ${ISOFORGE_SOURCE_DIR} -B ${STATIC_BUILD_DIR} -G ${GENERATOR}
      -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_BUILD_TYPE=${BUILD_TYPE} "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}"
      -DBUILD_SHARED_LIBS=OFF -DISOFORGE_BUILD_TESTS=OFF -DISOFORGE_BUILD_VERIFY=OFF
      -DISOFORGE_BUILD_BENCH=OFF -DISOFORGE_BUILD_FUZZERS=OFF
      -DISOFORGE_X86_64_V2=${X86_64_V2} "-DISOFORGE_SANITIZE=${SANITIZE}")
  run(${CMAKE_COMMAND} --build ${STATIC_BUILD_DIR} --target isoforge)
  run(${CMAKE_COMMAND} --install ${STATIC_BUILD_DIR} --prefix ${prefix} --component Development)
else()
  run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
endif()

# The prefix holds the library of the requested kind and only that.
file(GLOB_RECURSE archives ${prefix}/lib*/libisoforge.a)
file(GLOB_RECURSE shared ${prefix}/lib*/libisoforge.so*)
if(LIBRARY_TYPE STREQUAL "STATIC_LIBRARY")
  if(NOT archives OR shared)
    message(FATAL_ERROR "a static build must install libisoforge.a only; found: ${archives} ${shared}")
  endif()
elseif(NOT shared OR archives)
  message(FATAL_ERROR "a shared build must install libisoforge.so only; found: ${archives} ${shared}")
endif()
# The package config names no directory of the build machine: dependencies are found again, by
# name, where the consumer is configured.
file(GLOB config_files ${prefix}/lib*/cmake/isoforge/*.cmake)
foreach(f IN LISTS config_files)
  file(READ ${f} text)
  foreach(path IN ITEMS /usr/lib /usr/local/lib ${BUILD_DIR} ${STATIC_BUILD_DIR})
    string(FIND "${text}" "${path}" at)
    if(at GREATER_EQUAL 0)
      message(FATAL_ERROR "${f} hard-codes the path ${path}")
    endif()
  endforeach()
endforeach()

# The consumer's sources: tests/consumer/ plus the C++ example of the README, taken from the
# README itself so the two cannot drift apart.
file(COPY ${SOURCE_DIR}/ DESTINATION ${WORK_DIR}/src)
file(READ ${SOURCE_DIR}/../../README.md readme)
string(FIND "${readme}" "```cpp\n" begin)
if(begin LESS 0)
  message(FATAL_ERROR "README.md has no ```cpp block")
endif()
math(EXPR begin "${begin} + 7")
string(SUBSTRING "${readme}" ${begin} -1 readme)
string(FIND "${readme}" "```" end)
string(SUBSTRING "${readme}" 0 ${end} example)
file(WRITE ${WORK_DIR}/src/readme_example.cpp "${example}")

run(${CMAKE_COMMAND} -S ${WORK_DIR}/src -B ${WORK_DIR}/build -G ${GENERATOR}
    -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix})
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
# A shared libisoforge is found through the consumer's RPATH (CMake sets it for build trees).
run(${WORK_DIR}/build/consumer ${DATA_FILE} ${WORK_DIR})
# The README's example runs from a directory that has data/ in it.
file(CREATE_LINK ${DATA_DIR} ${WORK_DIR}/data SYMBOLIC)
execute_process(COMMAND ${WORK_DIR}/build/readme_example WORKING_DIRECTORY ${WORK_DIR}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}")
if(NOT rc EQUAL 0 OR NOT out MATCHES "47025 points, density 0.19" OR
   NOT out MATCHES "\n[1-9][0-9]* triangles")
  message(FATAL_ERROR "README example failed (${rc}): ${out}${err}")
endif()
if(NOT EXISTS ${WORK_DIR}/density.vtp)
  message(FATAL_ERROR "README example did not write density.vtp")
endif()
