# The linker for the project's own targets: GNU gold (binutils ships it beside the default BFD
# linker) when the compiler can use it. The suite links some sixty test executables against the
# static libraries, in each of .ci/run's two builds, and gold links the same objects into the same
# programs faster. -DRADAR_NDT_LINKER=default keeps the toolchain's own. The libFuzzer build keeps
# clang's default.
set(RADAR_NDT_LINKER "gold" CACHE STRING "Linker of the project's targets: gold, or default (the toolchain's)")
set_property(CACHE RADAR_NDT_LINKER PROPERTY STRINGS gold default)
if(RADAR_NDT_LINKER STREQUAL "gold" AND CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang" AND NOT RADAR_NDT_FUZZ)
  include(CheckCXXSourceCompiles)
  set(CMAKE_REQUIRED_LINK_OPTIONS -fuse-ld=gold)
  check_cxx_source_compiles("int main() { return 0; }" RADAR_NDT_HAS_GOLD)
  unset(CMAKE_REQUIRED_LINK_OPTIONS)
  if(RADAR_NDT_HAS_GOLD)
    add_link_options(-fuse-ld=gold)
  endif()
endif()
