# Script for the consumer_package test (see tests/consumer.cmake).
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message("${out}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "command failed (${rc}): ${ARGN}\n${err}")
  endif()
endfunction()

run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
run(${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${WORK_DIR}/build -G ${GENERATOR}
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix})
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
# The installed library is found through the consumer's RPATH (CMake sets it for build trees).
run(${WORK_DIR}/build/consumer ${DATA_FILE} ${WORK_DIR})
# The README's example runs from a directory that has data/ in it.
file(CREATE_LINK ${DATA_DIR} ${WORK_DIR}/data SYMBOLIC)
execute_process(COMMAND ${WORK_DIR}/build/readme_example WORKING_DIRECTORY ${WORK_DIR}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}")
if(NOT rc EQUAL 0 OR NOT out MATCHES "47025 points, density 0.19")
  message(FATAL_ERROR "README example failed (${rc}): ${out}${err}")
endif()
if(NOT EXISTS ${WORK_DIR}/combustor.vts)
  message(FATAL_ERROR "README example did not write combustor.vts")
endif()
