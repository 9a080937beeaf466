#!/usr/bin/env bash
# Fuzz every reader with libFuzzer (clang, ASan + UBSan).
#
#   test/fuzz/run.sh [SECONDS_PER_TARGET] [TARGET ...]      (default: 60 s each, all targets)
#
# Builds build-fuzz (clang, -DRADAR_NDT_FUZZ=ON), builds seed corpora in build-fuzz/seeds/<target>
# from ../shared/data (RADIATE and nuScenes files, the real Oxford scans, index and ground truth,
# the Oxford ground-truth trajectories, the real Boreas scan and pose file) and from
# radar_sim output (built in ./build), then runs each target for SECONDS on the grown corpus in
# build-fuzz/corpus/<target>. A crash, leak, sanitizer report, timeout (10 s an input) or an
# allocation over 2 GB stops the target, leaves the input in build-fuzz/artifacts/<target>/, and the
# script exits non-zero after the remaining targets ran.
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds=${1:-60}
shift || true
all=(fuzz_polar_png fuzz_nuscenes_pcd fuzz_nuscenes_tables fuzz_trajectory fuzz_oxford_odometry_csv fuzz_sequence_index
     fuzz_sensor_description fuzz_view_of_delft fuzz_motion_sensors)
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=("${all[@]}")
data=../shared/data
out=build-fuzz

command -v clang++ >/dev/null || { echo "fuzz: clang++ not found (Debian: apt-get install clang libclang-rt-14-dev)" >&2; exit 2; }
cmake -S . -B "$out" -G Ninja -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DRADAR_NDT_FUZZ=ON \
  -DRADAR_NDT_BUILD_APPS=OFF -DRADAR_NDT_BUILD_TESTS=OFF >/dev/null
cmake --build "$out" --target "${targets[@]}"

# ---- seed corpora -----------------------------------------------------------------------------
seeds=$out/seeds
rm -rf "$seeds"
for t in "${all[@]}"; do mkdir -p "$seeds/$t" "$out/corpus/$t" "$out/artifacts/$t"; done
prefixed() { { printf "\\x$(printf %02x "$1")"; cat "$2"; } > "$3"; }  # selector byte + file
# The first 20 entries of a JSON list (a real table or CAN bus file cut to a fuzzable size).
first_entries() { python3 -c "import json,sys; json.dump(json.load(open(sys.argv[1]))[:20], open(sys.argv[2],'w'), indent=1)" "$1" "$2"; }

# Simulator output (Oxford layout), small scans so the fuzzer runs fast.
if cmake -S . -B build -G Ninja >/dev/null && cmake --build build --target radar_sim >/dev/null; then
  sim=$out/sim
  rm -rf "$sim"
  ./build/apps/radar_sim --type scanning --frames 3 --out "$sim" -q --set azimuths=32 --set bins=200
  i=0; for f in "$sim"/radar/*.png; do prefixed 0 "$f" "$seeds/fuzz_polar_png/sim_$i.png"; i=$((i+1)); done
  # The first scan as other tools store it (gAMA, RGB, RGBA, grey + alpha, palette, Adam7, 16-bit).
  python3 test/fuzz/png_variants.py "$(ls "$sim"/radar/*.png | head -1)" "$out/variant"
  for f in "$out"/variant_*.png; do prefixed 0 "$f" "$seeds/fuzz_polar_png/$(basename "$f")"; rm "$f"; done
  cp "$sim/gt/radar_odometry.csv" "$seeds/fuzz_oxford_odometry_csv/sim.csv"
  prefixed 0 "$sim/radar.timestamps" "$seeds/fuzz_sequence_index/sim_radar.timestamps"
  prefixed 1 "$sim/gt/poses.txt" "$seeds/fuzz_trajectory/sim_poses_kitti.txt"
  # A Boreas-layout sequence (2024-dated, chirp flags), its pose file and a leaderboard file.
  rm -rf "$sim-boreas"
  ./build/apps/radar_sim --layout boreas --start-stamp 1733239501983835 --chirp-flags --frames 3 --out "$sim-boreas" \
    -q --set azimuths=32 --set bins=200
  i=0; for f in "$sim-boreas"/radar/*.png; do prefixed 4 "$f" "$seeds/fuzz_polar_png/boreas_sim_$i.png"; i=$((i+1)); done
  prefixed 0 "$sim-boreas/applanix/radar_poses.csv" "$seeds/fuzz_trajectory/boreas_sim_poses_auto.csv"
  awk '{printf "%d", 1733239501983835 + NR * 250000; for (i = 1; i <= NF; ++i) printf " %s", $i; print ""}' \
    "$sim-boreas/gt/poses.txt" > "$out/leaderboard.txt"
  prefixed 3 "$out/leaderboard.txt" "$seeds/fuzz_trajectory/boreas_sim_odometry.txt"; rm "$out/leaderboard.txt"
else
  echo "fuzz: radar_sim did not build: no simulator seeds" >&2
fi

if [ -d "$data" ]; then
  i=0; for f in $(ls "$data"/radiate-tiny-foggy/Navtech_Polar/*.png | head -3); do
    prefixed 1 "$f" "$seeds/fuzz_polar_png/radiate_$i.png"; i=$((i+1)); done
  prefixed 1 "$data/radiate-tiny-foggy/Navtech_Polar.txt" "$seeds/fuzz_sequence_index/Navtech_Polar.txt"
  # A few sweeps of every radar channel, the smallest (empty ones included) and some large.
  for ch in "$data"/nuscenes-mini-radar/sweeps/*/; do
    for f in $(ls -S "$ch" | tail -2) $(ls -S "$ch" | head -1); do cp "$ch/$f" "$seeds/fuzz_nuscenes_pcd/"; done
  done
  tables=$data/nuscenes-mini-radar/v1.0-mini
  k=0; for t in sensor calibrated_sensor ego_pose sample scene log sample_data; do
    # the first rows of each real table (the big ones cut to 20 rows), behind the target's selector
    first_entries "$tables/$t.json" "$out/$t.json"
    prefixed $k "$out/$t.json" "$seeds/fuzz_nuscenes_tables/real_$t.json"; rm "$out/$t.json"; k=$((k+1))
  done
  # The first messages of a real scene's CAN bus files: ms_imu (yaw rate, 6-axis) and the wheels.
  for t in ms_imu zoe_veh_info; do
    first_entries "$data/nuscenes-mini-radar/can_bus/scene-0061_$t.json" "$out/$t.json"
  done
  prefixed 1 "$out/ms_imu.json" "$seeds/fuzz_motion_sensors/real_ms_imu_yaw.json"
  prefixed 3 "$out/ms_imu.json" "$seeds/fuzz_motion_sensors/real_ms_imu.json"
  prefixed 2 "$out/zoe_veh_info.json" "$seeds/fuzz_motion_sensors/real_zoe_veh_info.json"
  rm "$out/ms_imu.json" "$out/zoe_veh_info.json"
  for f in "$data"/oxford-radar-gt/*.txt; do
    head -40 "$f" > "$out/gt.txt"
    prefixed 0 "$out/gt.txt" "$seeds/fuzz_trajectory/$(basename "$f" .txt)_auto.txt"
    prefixed 1 "$out/gt.txt" "$seeds/fuzz_trajectory/$(basename "$f" .txt)_kitti.txt"
    rm "$out/gt.txt"
  done
  # The real Oxford scans: one polar PNG (full size, 400 x 3779), the index and the first rows of
  # the dataset's own radar_odometry.csv.
  real=$data/oxford-radar-real
  if [ -d "$real" ]; then
    prefixed 0 "$(ls "$real"/radar/*.png | head -1)" "$seeds/fuzz_polar_png/oxford_real_0.png"
    prefixed 0 "$real/radar.timestamps" "$seeds/fuzz_sequence_index/oxford_real_radar.timestamps"
    head -21 "$real/gt/radar_odometry.csv" > "$seeds/fuzz_oxford_odometry_csv/oxford_real.csv"
  fi
  boreas=$data/boreas-sample
  if [ -d "$boreas" ]; then
    prefixed 4 "$boreas/radar-2024-12-03/radar/1733239501983835.png" "$seeds/fuzz_polar_png/boreas_real_2024.png"
    head -30 "$boreas/boreas-2021-08-05-13-34/applanix/radar_poses.csv" > "$out/poses.csv"
    prefixed 0 "$out/poses.csv" "$seeds/fuzz_trajectory/boreas_real_poses_auto.csv"; rm "$out/poses.csv"
  fi
  head -40 "$data/kitti-metric-fixture/gt.txt" > "$out/fixture.txt"
  prefixed 1 "$out/fixture.txt" "$seeds/fuzz_trajectory/fixture_kitti.txt"; rm "$out/fixture.txt"
else
  echo "fuzz: $data is absent: seeds from the simulator and built-in tables only" >&2
fi
prefixed 2 test/data/demo_gt.txt "$seeds/fuzz_trajectory/demo_tum.txt"
# View-of-Delft's three files as its devkit lays them out, and a Boreas applanix/imu.csv as the
# released files lay it out (no real one is in ../shared/data); real nuScenes CAN bus files above.
python3 test/fuzz/motion_seeds.py "$seeds"
mkdir -p "$seeds/fuzz_sensor_description"
cp config/sensors/*.yaml "$seeds/fuzz_sensor_description/"
prefixed 0 test/data/demo_gt.txt "$seeds/fuzz_trajectory/demo_auto.txt"
RADAR_NDT_FUZZ_WRITE_SEEDS="$seeds/fuzz_nuscenes_tables" "$out/test/fuzz/fuzz_nuscenes_tables" 2>/dev/null || true

# ---- run ----------------------------------------------------------------------------------------
failed=()
for t in "${targets[@]}"; do
  echo "== $t: ${seconds} s"
  if ! "$out/test/fuzz/$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=2048 \
       -print_final_stats=1 -artifact_prefix="$out/artifacts/$t/" "$out/corpus/$t" "$seeds/$t" \
       > "$out/$t.log" 2>&1; then
    failed+=("$t")
    echo "   FINDING: see $out/$t.log and $out/artifacts/$t/" >&2
  fi
  grep -E "^stat::number_of_executed_units|^#[0-9]+.*DONE" "$out/$t.log" | tail -2 | sed 's/^/   /'
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz: findings in ${failed[*]}" >&2
  exit 1
fi
echo "fuzz: ${#targets[@]} targets, ${seconds} s each, no finding"
