# FindLibdeflate: libdeflate (Debian libdeflate-dev), which ships a pkg-config file but no CMake
# package in the Debian release this project targets. Defines Libdeflate::Libdeflate and
# Libdeflate_FOUND / Libdeflate_VERSION. Installed beside RadarNDTConfig.cmake, which finds it again
# for the exported RadarNDT::io.
find_package(PkgConfig QUIET)
if(PkgConfig_FOUND)
  pkg_check_modules(PC_Libdeflate QUIET libdeflate)
endif()
find_path(Libdeflate_INCLUDE_DIR NAMES libdeflate.h HINTS ${PC_Libdeflate_INCLUDE_DIRS})
find_library(Libdeflate_LIBRARY NAMES deflate libdeflate HINTS ${PC_Libdeflate_LIBRARY_DIRS})
set(Libdeflate_VERSION ${PC_Libdeflate_VERSION})
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(Libdeflate REQUIRED_VARS Libdeflate_LIBRARY Libdeflate_INCLUDE_DIR
                                  VERSION_VAR Libdeflate_VERSION)
if(Libdeflate_FOUND AND NOT TARGET Libdeflate::Libdeflate)
  add_library(Libdeflate::Libdeflate UNKNOWN IMPORTED)
  set_target_properties(Libdeflate::Libdeflate PROPERTIES
    IMPORTED_LOCATION "${Libdeflate_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${Libdeflate_INCLUDE_DIR}")
endif()
mark_as_advanced(Libdeflate_INCLUDE_DIR Libdeflate_LIBRARY)
