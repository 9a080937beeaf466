# Installs the build tree into a temporary prefix, then configures, builds and runs test/consumer
# against it with find_package(RadarNDT): the proof that the installed package works.
file(REMOVE_RECURSE "${WORK_DIR}")
set(prefix "${WORK_DIR}/prefix")
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message("${out}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${err}")
  endif()
endfunction()
run(${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${prefix}")
run(${CMAKE_COMMAND} -S "${CONSUMER_SOURCE}" -B "${WORK_DIR}/build" -G "${GENERATOR}"
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix}
    # A sanitizer build installs instrumented static libraries: the consumer links the runtimes,
    # and compiles with them too, with the library's Eigen allocator setting (Eigen allocates
    # differently under AddressSanitizer unless told otherwise; a cloud the library allocated must
    # be freed the same way: cmake/RadarNDTSanitizers.cmake).
    "-DCMAKE_CXX_FLAGS=${CONSUMER_SANITIZER_FLAGS}"
    "-DCMAKE_EXE_LINKER_FLAGS=${CONSUMER_SANITIZER_FLAGS}")
run(${CMAKE_COMMAND} --build "${WORK_DIR}/build")
run("${WORK_DIR}/build/consumer")
