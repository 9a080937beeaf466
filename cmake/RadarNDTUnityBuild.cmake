# Unity builds of the project's libraries, multi-file programs and test executables (the unit tests
# one executable a layer). Their translation units are short and parse-bound: each one parses Eigen, PCL's
# point cloud and registration and the pipeline headers above them before its own few hundred
# lines, and .ci/run compiles everything twice (Release, then ASan + UBSan). CMake compiles a
# target's sources in batches of eight, one translation unit a batch, so the headers are parsed
# once a batch. Sources that define a macro before PCL's headers (PCL_NO_PRECOMPILE, the template
# instantiation units) are compiled alone: radar_ndt_compile_alone(). The price: file-local names
# must be unique across a target (no two anonymous-namespace helpers of one name), and editing one
# file recompiles its batch. -DRADAR_NDT_UNITY_BUILD=OFF compiles every file on its own
# (docs/testing.md: the configurations).
option(RADAR_NDT_UNITY_BUILD "Compile the project's libraries and tests in batches of sources (faster full builds)" ON)

function(radar_ndt_unity_build target)
  if(RADAR_NDT_UNITY_BUILD)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8)
    if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
      # In a batch every source is an included file, which GCC takes for a header: a class of one
      # source holding a type of its anonymous namespace (a stream's Impl) is then reported.
      target_compile_options(${target} PRIVATE -Wno-subobject-linkage)
    endif()
  endif()
endfunction()

# radar_ndt_compile_alone(<sources>...): kept out of the batches (relative to the calling folder).
function(radar_ndt_compile_alone)
  set_source_files_properties(${ARGN} PROPERTIES SKIP_UNITY_BUILD_INCLUSION ON)
endfunction()
