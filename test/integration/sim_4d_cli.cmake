cmake_minimum_required(VERSION 3.16)
# radar_sim --type 4d writes a folder radar_odometry reads (run with cmake -P): the Oculii Eagle
# along the built-in drive with a MEMS IMU, as NTU4DRadLM's bags lay it out; radar_odometry reads
# the bag through the sensors.yaml written beside it, evaluates against its /gt and writes as many
# poses as there are scans, each time one of groundtruth.txt's. Then Snail-Radar's ARS548, which sits
# at the base frame's origin: the planar run's Doppler fit gives the forward speed alone there, and
# every cycle must still have a valid ego-velocity.
file(REMOVE_RECURSE "${OUT}")
execute_process(COMMAND "${SIM}" --type 4d --preset oculii_eagle --imu mems --frames 60 --out "${OUT}/seq"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "radar_sim --type 4d failed (${rc})")
endif()
foreach(expected "60 scans at 10 Hz" "radar.bag (60 scans on /radar_enhanced_pcl" "IMU messages, 60 /gt")
  string(FIND "${out}" "${expected}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "radar_sim: expected '${expected}' in its output")
  endif()
endforeach()
file(GLOB pcds "${OUT}/seq/radar/*.pcd")
list(LENGTH pcds n)
if(NOT n EQUAL 60)
  message(FATAL_ERROR "expected 60 scans in ${OUT}/seq/radar, found ${n}")
endif()
execute_process(COMMAND "${APP}" --format rosbag --bag "${OUT}/seq/radar.bag" --sensors "${OUT}/seq/sensors.yaml"
                        --eval --out "${OUT}/traj.txt"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "radar_odometry on the simulated bag failed (${rc})")
endif()
foreach(expected "60 cycles (reference eagle, 10.0 Hz)" "1m ")
  string(FIND "${out}${err}" "${expected}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "radar_odometry: expected '${expected}' in its output")
  endif()
endforeach()
file(STRINGS "${OUT}/traj.txt" est)
file(STRINGS "${OUT}/seq/groundtruth.txt" gt)
list(LENGTH est n_est)
list(LENGTH gt n_gt)
if(NOT n_est EQUAL 60 OR NOT n_gt EQUAL 60)
  message(FATAL_ERROR "expected 60 poses in the estimate and the truth, found ${n_est} and ${n_gt}")
endif()
list(GET est 10 e)
list(GET gt 10 g)
string(REGEX MATCH "^[0-9.]+" te "${e}")
string(REGEX MATCH "^[0-9.]+" tg "${g}")
if(NOT te STREQUAL tg)
  message(FATAL_ERROR "the 11th estimate's time ${te} is not the truth's ${tg}")
endif()

execute_process(COMMAND "${SIM}" --type 4d --preset ars548 --imu mems --frames 60 --out "${OUT}/ars548"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "radar_sim --type 4d --preset ars548 failed (${rc}): ${out}${err}")
endif()
execute_process(COMMAND "${APP}" --format rosbag --bag "${OUT}/ars548/radar.bag" --sensors "${OUT}/ars548/sensors.yaml"
                        --eval
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "radar_odometry on the simulated ARS548 bag failed (${rc})")
endif()
foreach(expected "60 cycles (reference ars548" "0 cycles without a valid ego-velocity"
                 "the forward speed alone (radars on the rear axle's line: the yaw rate left to the match) in 60 cycles")
  string(FIND "${out}${err}" "${expected}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "radar_odometry on the ARS548: expected '${expected}' in its output")
  endif()
endforeach()
