# isoforge_find_codecs([REQUIRED]): the compression libraries of the VTK XML reader and writer
# (src/io/vtk_xml_codecs.cpp), for isoforge's own build and for the installed package config of a
# static isoforge (installed beside isoforge-config.cmake). Debian's libdeflate-dev, liblz4-dev and
# liblzma-dev ship pkg-config files but no CMake package configs, so each becomes an imported
# target from pkg-config: PkgConfig::isoforge_libdeflate, PkgConfig::isoforge_lz4 and
# PkgConfig::isoforge_lzma (the names a static libisoforge's exported link interface refers to).
# Sets isoforge_codecs_FOUND.

include_guard(GLOBAL)

macro(isoforge_find_codecs)
  find_package(PkgConfig ${ARGN})
  set(isoforge_codecs_FOUND FALSE)
  if(PKG_CONFIG_FOUND)
    foreach(_isoforge_codec IN ITEMS "libdeflate;libdeflate>=1.10" "lz4;liblz4" "lzma;liblzma")
      list(GET _isoforge_codec 0 _isoforge_codec_name)
      list(GET _isoforge_codec 1 _isoforge_codec_module)
      if(NOT TARGET PkgConfig::isoforge_${_isoforge_codec_name})
        pkg_check_modules(isoforge_${_isoforge_codec_name} ${ARGN} QUIET IMPORTED_TARGET
                          ${_isoforge_codec_module})
      endif()
    endforeach()
    if(TARGET PkgConfig::isoforge_libdeflate AND TARGET PkgConfig::isoforge_lz4
       AND TARGET PkgConfig::isoforge_lzma)
      set(isoforge_codecs_FOUND TRUE)
    endif()
  endif()
  unset(_isoforge_codec)
  unset(_isoforge_codec_name)
  unset(_isoforge_codec_module)
endmacro()
