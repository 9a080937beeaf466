# radar_ndt_set_warnings(<target>): the project's warning set, kept clean.
# Third-party headers (PCL, Eigen, VTK, Boost) come in as SYSTEM includes so
# their warnings do not drown ours.
function(radar_ndt_set_warnings target)
  if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
    target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic)
  endif()
  if(CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    # PointRadar uses PCL's anonymous-union layout (PCL_ADD_POINT4D), which clang flags as GNU.
    target_compile_options(${target} PRIVATE -Wno-gnu-anonymous-struct -Wno-nested-anon-types)
  endif()
endfunction()
