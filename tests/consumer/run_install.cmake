# Script of the install_relocatable test (see tests/consumer.cmake): the installed programs run
# with LD_LIBRARY_PATH unset, from the install prefix and again after the prefix was moved
# elsewhere, so they find libisoforge through their relative RPATH ($ORIGIN/../lib).
#
#   BUILD_DIR     the build to install
#   WORK_DIR      scratch directory
#   DATA_DIR      the repository's data/
#   WITH_VERIFY   whether isoforge-verify is built (ISOFORGE_BUILD_VERIFY)
#   LIBRARY_TYPE  SHARED_LIBRARY or STATIC_LIBRARY
#   PYTHON        a Python 3 interpreter, for check_runpath.py
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})

# run(EXPECT regex COMMAND...): the command exits 0 and its output (stdout and stderr) matches
# the regex.
function(run)
  cmake_parse_arguments(PARSE_ARGV 0 arg "" "EXPECT" "COMMAND")
  execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=LD_LIBRARY_PATH ${arg_COMMAND}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  message("${arg_COMMAND}\n${out}")
  if(NOT rc EQUAL 0 OR NOT "${out}" MATCHES "${arg_EXPECT}")
    message(FATAL_ERROR "failed (exit ${rc}, expected output /${arg_EXPECT}/): ${arg_COMMAND}\n"
                        "${out}")
  endif()
  set(output "${out}" PARENT_SCOPE)
endfunction()

function(run_installed prefix)
  set(tmp ${WORK_DIR}/out)
  file(MAKE_DIRECTORY ${tmp})
  set(programs ${prefix}/bin/isoforge)
  run(EXPECT "^[0-9]+\\.[0-9]+\\.[0-9]+" COMMAND ${prefix}/bin/isoforge --version)
  run(EXPECT "20 x 20 x 20 samples"
      COMMAND ${prefix}/bin/isoforge sample -f "sphere(r=0.8)" -b -1 1 -1 1 -1 1 -d 20
              -o ${tmp}/sphere.vti)
  run(EXPECT "2156 cells" COMMAND ${prefix}/bin/isoforge contour ${tmp}/sphere.vti -v 0
                                 -o ${tmp}/sphere.vtp)
  # The OpenVDB parts: the commands' module and libisoforge_vdb (loaded on demand in a shared
  # build, from this prefix).
  run(EXPECT "active" COMMAND ${prefix}/bin/isoforge sample -f "sphere(r=0.8)" -b -1 1 -1 1 -1 1
                              -d 20 -o ${tmp}/sphere.vdb)
  run(EXPECT "cells" COMMAND ${prefix}/bin/isoforge contour ${tmp}/sphere.vdb -v 0
                             -o ${tmp}/sparse.vtp)
  run(EXPECT "wrote .*dense.vti" COMMAND ${prefix}/bin/isoforge convert ${tmp}/sphere.vdb
                                         ${tmp}/dense.vti)
  if(LIBRARY_TYPE STREQUAL "SHARED_LIBRARY")
    run(EXPECT "wrote" COMMAND ${CMAKE_COMMAND} -E env LD_DEBUG=files
                               ${prefix}/bin/isoforge contour ${tmp}/sphere.vdb -v 0
                               -o ${tmp}/sparse.vtp)
    foreach(name isoforge-vdb-commands.so libisoforge_vdb.so.0)
      if(NOT "${output}" MATCHES "calling init: ${prefix}/[^ ]*${name}")
        message(FATAL_ERROR "contour of a .vdb did not load ${name} from ${prefix}")
      endif()
    endforeach()
  endif()
  # Ceres: libisoforge_fit (loaded on demand in a shared build, from this prefix).
  run(EXPECT "radius: 0\\.(79|80)" COMMAND ${prefix}/bin/isoforge fit ${tmp}/sphere.vtp -p sphere)
  if(LIBRARY_TYPE STREQUAL "SHARED_LIBRARY")
    run(EXPECT "radius" COMMAND ${CMAKE_COMMAND} -E env LD_DEBUG=files
                                ${prefix}/bin/isoforge fit ${tmp}/sphere.vtp -p sphere)
    if(NOT "${output}" MATCHES "calling init: ${prefix}/[^ ]*libisoforge_fit.so.0")
      message(FATAL_ERROR "fit did not load libisoforge_fit.so.0 from ${prefix}")
    endif()
  endif()
  if(WITH_VERIFY)
    list(APPEND programs ${prefix}/bin/isoforge-verify)
    run(EXPECT "^[0-9]+\\.[0-9]+\\.[0-9]+" COMMAND ${prefix}/bin/isoforge-verify --version)
    run(EXPECT "closed: yes"
        COMMAND ${prefix}/bin/isoforge-verify mesh ${tmp}/sphere.vtp
                --require closed,manifold,oriented,no-self-intersections)
  endif()
  # Each program loads the libisoforge of this prefix (not one of the build tree).
  if(LIBRARY_TYPE STREQUAL "SHARED_LIBRARY")
    foreach(program IN LISTS programs)
      run(EXPECT "libisoforge" COMMAND ${CMAKE_COMMAND} -E env LD_TRACE_LOADED_OBJECTS=1 ${program})
      string(REGEX MATCH "libisoforge[^\n]*" line "${output}")
      string(FIND "${line}" "=> ${prefix}/" at)
      if(at LESS 0)
        message(FATAL_ERROR "${program} does not load libisoforge from ${prefix}: ${line}")
      endif()
    endforeach()
  endif()
  file(REMOVE_RECURSE ${tmp})
endfunction()

execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK_DIR}/prefix
                RESULT_VARIABLE rc OUTPUT_QUIET)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install ${BUILD_DIR} failed (${rc})")
endif()
run_installed(${WORK_DIR}/prefix)
# Installed files search for libraries only relative to themselves or in absolute directories.
run(EXPECT " 0 problems" COMMAND ${PYTHON} ${CMAKE_CURRENT_LIST_DIR}/check_runpath.py
                                 ${WORK_DIR}/prefix)

# Relocatable: the same prefix, moved to another directory (the original is gone).
file(MAKE_DIRECTORY ${WORK_DIR}/elsewhere)
file(RENAME ${WORK_DIR}/prefix ${WORK_DIR}/elsewhere/moved-prefix)
run_installed(${WORK_DIR}/elsewhere/moved-prefix)
