# consumer_package: install this build into a scratch prefix, then configure, build and run the
# separate project in tests/consumer/ against it with find_package(isoforge).
set(_consumer_dir ${CMAKE_CURRENT_BINARY_DIR}/consumer)
add_test(NAME consumer_package
  COMMAND ${CMAKE_COMMAND}
    -DBUILD_DIR=${PROJECT_BINARY_DIR}
    -DWORK_DIR=${_consumer_dir}
    -DSOURCE_DIR=${CMAKE_CURRENT_SOURCE_DIR}/consumer
    -DDATA_FILE=${PROJECT_SOURCE_DIR}/data/hello.vtk
    -DDATA_DIR=${PROJECT_SOURCE_DIR}/data
    -DGENERATOR=${CMAKE_GENERATOR}
    -P ${CMAKE_CURRENT_SOURCE_DIR}/consumer/run_consumer.cmake)
set_tests_properties(consumer_package PROPERTIES LABELS consumer TIMEOUT 600)
