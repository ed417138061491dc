# isoforge_find_openvdb([<find_package arguments>...]): find_package(OpenVDB ...) for isoforge's
# own build and for its installed package config (installed beside isoforge-config.cmake).
#
# OpenVDB 10 installs no package config, only a find module (FindOpenVDB.cmake, with its helper
# modules FindTBB, FindBlosc, ...) in <prefix>/<libdir>/cmake/OpenVDB. The module's directory is
# searched for at configure time, so nothing here names one distribution's path:
#   1. a FindOpenVDB.cmake already on CMAKE_MODULE_PATH is used as it is;
#   2. else the cache variable ISOFORGE_OPENVDB_MODULE_DIR (set it to override the search), found
#      under each of OpenVDB_ROOT (variable or environment), CMAKE_PREFIX_PATH (variable or
#      environment) and CMAKE_SYSTEM_PREFIX_PATH, in lib/<CMAKE_LIBRARY_ARCHITECTURE>/cmake/OpenVDB
#      (Debian, Ubuntu), lib64/cmake/OpenVDB and lib/cmake/OpenVDB (OpenVDB's default);
#   3. if neither exists, find_package runs unchanged (a future OpenVDB with a package config).
#
# The search runs in a function: FindOpenVDB sets BUILD_SHARED_LIBS=ON and Boost_USE_STATIC_LIBS=OFF
# in its caller's variable scope (a workaround for Boost 1.70), which would otherwise turn every
# later add_library() of the caller (isoforge itself, or a consumer's libraries) shared. Only
# OpenVDB_FOUND and OpenVDB_VERSION reach the caller; the imported targets are directory-wide.
#
# Find TBB before calling this: OpenVDB's FindTBB reuses existing TBB:: targets, while TBB's own
# package config, found after FindTBB made TBB::tbb alone, stops with "Some (but not all) targets
# in this export set were already defined".

include_guard(GLOBAL)

function(isoforge_find_openvdb)
  set(_module_dir "")
  foreach(_dir IN LISTS CMAKE_MODULE_PATH)
    if(EXISTS "${_dir}/FindOpenVDB.cmake")
      set(_module_dir "${_dir}")
      break()
    endif()
  endforeach()
  if(NOT _module_dir)
    file(TO_CMAKE_PATH "$ENV{OpenVDB_ROOT}" _env_root)
    file(TO_CMAKE_PATH "$ENV{CMAKE_PREFIX_PATH}" _env_prefixes)
    set(_candidates "")
    foreach(_prefix IN LISTS OpenVDB_ROOT _env_root CMAKE_PREFIX_PATH _env_prefixes
                             CMAKE_SYSTEM_PREFIX_PATH)
      if(CMAKE_LIBRARY_ARCHITECTURE)
        list(APPEND _candidates "${_prefix}/lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/OpenVDB")
      endif()
      list(APPEND _candidates "${_prefix}/lib64/cmake/OpenVDB" "${_prefix}/lib/cmake/OpenVDB")
    endforeach()
    find_path(ISOFORGE_OPENVDB_MODULE_DIR FindOpenVDB.cmake PATHS ${_candidates} NO_DEFAULT_PATH
              DOC "Directory of OpenVDB's FindOpenVDB.cmake (searched under the standard prefixes)")
    mark_as_advanced(ISOFORGE_OPENVDB_MODULE_DIR)
    if(ISOFORGE_OPENVDB_MODULE_DIR)
      set(_module_dir "${ISOFORGE_OPENVDB_MODULE_DIR}")
      list(APPEND CMAKE_MODULE_PATH "${_module_dir}")
    endif()
  endif()
  find_package(OpenVDB ${ARGN})
  set(OpenVDB_FOUND "${OpenVDB_FOUND}" PARENT_SCOPE)
  set(OpenVDB_VERSION "${OpenVDB_VERSION}" PARENT_SCOPE)
endfunction()
