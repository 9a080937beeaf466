# Sanitizer and fuzzing builds, for every target of the project (not for the installed package).
#
# RADAR_NDT_SANITIZE=ON: AddressSanitizer + UndefinedBehaviorSanitizer, any UB report is fatal
#   (-fno-sanitize-recover), -O1 -g1 so reports have usable stacks (file and line: -g1's line tables;
#   full -g costs a quarter more compile time for no better report). The README's test command
#   builds this configuration in build-asan and runs the suite in it (docs/testing.md says which tests
#   it leaves out).
# RADAR_NDT_FUZZ=ON (clang only): the libraries are compiled with -fsanitize=fuzzer-no-link plus ASan
#   and UBSan so libFuzzer sees their coverage; the fuzz targets in test/fuzz/ link -fsanitize=fuzzer.
# Eigen switches to its own ("handmade") aligned allocator when it sees __SANITIZE_ADDRESS__, while
# Debian's PCL libraries, built without ASan, allocate Eigen members with plain malloc: an object
# one side allocates and the other frees (PCL's NDT destroyed in our code) would be freed with the
# wrong allocator. EIGEN_MALLOC_ALREADY_ALIGNED=1 keeps our code on PCL's allocator (x86-64 malloc,
# ASan's included, returns 16-byte aligned memory).
set(_radar_ndt_san_flags -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer -O1 -g1
                         -DEIGEN_MALLOC_ALREADY_ALIGNED=1)
if(RADAR_NDT_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "RADAR_NDT_FUZZ needs clang (libFuzzer): configure with -DCMAKE_CXX_COMPILER=clang++ "
                        "-DCMAKE_C_COMPILER=clang (Debian: clang, libclang-rt-14-dev)")
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link ${_radar_ndt_san_flags})
  add_link_options(-fsanitize=address,undefined)
elseif(RADAR_NDT_SANITIZE)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
    message(FATAL_ERROR "RADAR_NDT_SANITIZE needs GCC or clang")
  endif()
  add_compile_options(${_radar_ndt_san_flags})
  add_link_options(-fsanitize=address,undefined)
endif()
