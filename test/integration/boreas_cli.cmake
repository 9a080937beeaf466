cmake_minimum_required(VERSION 3.19)
# Boreas end to end (run with cmake -P): radar_sim writes a Boreas-layout drive, radar_odometry
# runs it with --eval and writes the leaderboard's odometry file, radar_eval reads that file back
# against the sequence's applanix/radar_poses.csv and must give the same errors. Then the same on a
# drive from the real Boreas pose file (when ../shared/data is there), and a 2024-dated drive with
# chirp flags (the 0.04381 m bins, 6848 of them).
file(REMOVE_RECURSE "${OUT}")

function(run_and_check name)
  cmake_parse_arguments(A "" "" "SIM_ARGS;ODO_ARGS" ${ARGN})
  set(seq "${OUT}/${name}")
  execute_process(COMMAND "${SIM}" --layout boreas ${A_SIM_ARGS} --out "${seq}" -q RESULT_VARIABLE rc OUTPUT_VARIABLE so ERROR_VARIABLE se)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${name}: radar_sim failed (${rc}): ${so}${se}")
  endif()
  file(GLOB scans "${seq}/radar/*.png")
  list(LENGTH scans n)
  if(NOT n EQUAL 40)
    message(FATAL_ERROR "${name}: expected 40 scans in ${seq}/radar, found ${n}")
  endif()
  file(STRINGS "${seq}/applanix/radar_poses.csv" header LIMIT_COUNT 1)
  if(NOT header STREQUAL "GPSTime,easting,northing,altitude,vel_east,vel_north,vel_up,roll,pitch,heading,angvel_z,angvel_y,angvel_x")
    message(FATAL_ERROR "${name}: unexpected pose file header '${header}'")
  endif()
  execute_process(COMMAND "${APP}" --format boreas --sequence "${seq}" --eval --metric frame,ate --json -q
                          --out "${OUT}/${name}.txt" --out-format boreas ${A_ODO_ARGS}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE json ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${name}: radar_odometry exited ${rc}: ${json}${err}")
  endif()
  string(JSON matched GET "${json}" matched)
  string(JSON frame_m GET "${json}" metrics frame trans_err_m)
  string(JSON frame_deg GET "${json}" metrics frame rot_err_deg)
  message("${name}: matched ${matched}, frame ${frame_m} m ${frame_deg} deg")
  if(matched LESS 35)
    message(FATAL_ERROR "${name}: only ${matched} of 39 scans matched")
  endif()
  # A moving drive: a quarter of the frame error of standing still would not pass these.
  if(frame_m GREATER 0.08 OR frame_deg GREATER 0.2)
    message(FATAL_ERROR "${name}: frame errors ${frame_m} m / ${frame_deg} deg are too large")
  endif()
  file(STRINGS "${OUT}/${name}.txt" lines)
  list(LENGTH lines n)
  list(GET lines 0 first)
  if(NOT n EQUAL 40 OR NOT first MATCHES "^[0-9]+ 1 0 0 0 0 1 0 0 0 0 1 0$")
    message(FATAL_ERROR "${name}: the leaderboard file has ${n} lines, the first '${first}'")
  endif()
  execute_process(COMMAND "${EVAL}" --gt "${seq}/applanix/radar_poses.csv" --est "${OUT}/${name}.txt" --metric frame,ate --json
                  RESULT_VARIABLE rc OUTPUT_VARIABLE ejson ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${name}: radar_eval exited ${rc}: ${err}")
  endif()
  string(JSON eval_m GET "${ejson}" metrics frame trans_err_m)
  # The file keeps 12 significant digits: the errors agree to 1e-6 m.
  string(SUBSTRING "${eval_m}" 0 8 eval_short)
  string(SUBSTRING "${frame_m}" 0 8 frame_short)
  if(NOT eval_short STREQUAL frame_short)
    message(FATAL_ERROR "${name}: radar_eval on the leaderboard file gives frame ${eval_m} m, radar_odometry ${frame_m} m")
  endif()
  set(last_json "${json}" PARENT_SCOPE)
endfunction()

# The built-in drive dated 2021 (0.0596 m bins, 3360 of them, no chirp types).
run_and_check(builtin_2021 SIM_ARGS --frames 40 --start 40 --start-stamp 1628185286559054)
# 2024-dated with chirp flags: 6848 bins of 0.04381 m. The simulator's scans are as bright as
# Oxford's, not as the real 2024 scan, so the paper's threshold is given over the chirp default.
run_and_check(builtin_2024_chirps SIM_ARGS --frames 40 --start 40 --start-stamp 1733239501983835 --chirp-flags
              ODO_ARGS --threshold 0.333 --power-shift 0.333)
# A TUM trajectory timed from 0 s (a straight line at 10 m/s): not a date, so the scans are dated
# 2019-01-10 as the default start stamp says, and the reader takes their pose file.
set(tum "${OUT}/straight.tum")
file(WRITE "${tum}" "")
foreach(k RANGE 0 49)
  math(EXPR ms "${k} * 250")
  math(EXPR dm "${k} * 25")
  file(APPEND "${tum}" "${ms}e-3 ${dm}e-1 0 0 0 0 0 1\n")
endforeach()
run_and_check(tum_from_zero SIM_ARGS --trajectory "${tum}" --start 5 --frames 40)
file(GLOB tum_scans "${OUT}/tum_from_zero/radar/15471*.png")
if(NOT tum_scans)
  message(FATAL_ERROR "tum_from_zero: the scans are not dated from 1547120000000000")
endif()
# From the real Boreas pose file, where the car drives at about 14 m/s.
set(poses "${DATA}/boreas-sample/boreas-2021-08-05-13-34/applanix/radar_poses.csv")
if(EXISTS "${poses}")
  run_and_check(real_poses SIM_ARGS --trajectory "${poses}" --start 1600 --frames 40)
else()
  message("no ${poses} (../shared/data is absent): skipping the drive from the real pose file")
endif()
