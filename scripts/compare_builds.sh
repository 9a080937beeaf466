#!/usr/bin/env bash
# Builds two revisions of RadarNDT side by side and checks that their outputs are bit-identical,
# file by file: what a refactoring must show before it lands.
#
#   scripts/compare_builds.sh BASE [HEAD]
#
# BASE and HEAD are git revisions of this repository; HEAD defaults to HEAD, and "." means the
# working tree as it is (uncommitted changes included). Each is exported and built (Release, apps
# only) under $COMPARE_DIR (default /tmp/radar_ndt_compare); a revision's outputs are kept there
# per commit, so comparing against the same BASE again reruns only HEAD.
#
# Compared, with ../shared/data beside the checkout:
#  1. the demo (`cmake --build B --target demo`): both simulated sequences and both trajectories;
#  2. `radar_odometry --format nuscenes --scene all --method M --out` for every method;
#  3. the two paper tables (`radar_paper_tables`, or `radar_odometry --table` in revisions before
#     it existed) as JSON with the run-time columns removed (they are wall-clock timings: the
#     per-cycle and per-stage milliseconds);
#  4. `radar_sim` on the first 400 scans from pose 1000 of 2019-01-16-13-42-28 (seed 1) and
#     `radar_odometry --format oxford --out` on that sequence for ours, PCL's NDT and PCL's ICP;
#  5. the car's sensors (`--imu --wheels`, `wheel-gyro`), a scene's and the real Oxford scans'
#     summary JSON and steps CSV without their timings, the real Oxford and RADIATE scans, a
#     simulated Boreas drive with its gyro (`--imu`), and, in builds with ROS, bags: a scene's
#     (`--imu`), the real TI bag's and the real Oxford scans' written as a bag.
# Exit code 0 when every file is identical, 1 otherwise (each difference is listed).
set -euo pipefail

if [ $# -lt 1 ] || [ "$1" = "-h" ] || [ "$1" = "--help" ]; then
  sed -n '2,24p' "$0" | sed 's/^# \{0,1\}//'
  exit 2
fi
root=$(cd "$(dirname "$0")/.." && pwd)
data=$(cd "$root/../shared/data" 2>/dev/null && pwd) || { echo "compare_builds: ../shared/data is missing beside $root" >&2; exit 2; }
work=${COMPARE_DIR:-/tmp/radar_ndt_compare}
mkdir -p "$work"

# Exports revision $1 into $work/src-<id> and prints <id> (the commit, or "worktree").
export_rev() {
  local rev=$1 id dir
  if [ "$rev" = "." ]; then
    id=worktree
    dir=$work/src-$id
    rm -rf "$dir" && mkdir -p "$dir"
    (cd "$root" && git ls-files -co --exclude-standard -z | xargs -0 -I{} cp --parents {} "$dir/" 2>/dev/null) || true
  else
    id=$(git -C "$root" rev-parse --verify "$rev^{commit}")
    dir=$work/src-$id
    if [ ! -f "$dir/CMakeLists.txt" ]; then
      rm -rf "$dir" && mkdir -p "$dir"
      git -C "$root" archive "$id" | tar -x -C "$dir"
    fi
  fi
  echo "$id"
}

# Builds and runs everything for source id $1 into $work/out-<id> (skipped when already complete).
run_rev() {
  local id=$1 src=$work/src-$1 bld=$work/build-$1 out=$work/out-$1
  if [ "$id" != worktree ] && [ -f "$out/.complete" ]; then
    echo "[$id] outputs cached in $out" >&2
    return
  fi
  rm -rf "$out" && mkdir -p "$out"
  echo "[$id] building in $bld" >&2
  cmake -S "$src" -B "$bld" -G Ninja -DCMAKE_BUILD_TYPE=Release -DRADAR_NDT_BUILD_TESTS=OFF >"$out/configure.log"
  cmake --build "$bld" >"$out/build.log"
  local bin=$bld/apps
  echo "[$id] demo" >&2
  cmake --build "$bld" --target demo >"$out/demo.log" 2>&1
  cp "$bld/demo/scanning_traj.txt" "$bld/demo/automotive_traj.txt" "$out/"
  (cd "$bld/demo" && find scanning automotive -type f | sort | xargs sha256sum) >"$out/demo_sequences.sha256"

  echo "[$id] nuScenes, every method" >&2
  for m in pw-ndt pcl-ndt pcl-icp doppler rapp-ndt; do
    "$bin/radar_odometry" --format nuscenes --dataroot "$data/nuscenes-mini-radar" --scene all --method "$m" \
      --out "$out/nuscenes_$m.txt" -q >"$out/nuscenes_$m.log"
  done

  echo "[$id] simulated Oxford sequence and scanning runs" >&2
  local seq=$bld/oxford_seq
  rm -rf "$seq"
  "$bin/radar_sim" --type scanning --trajectory "$data/oxford-radar-gt/2019-01-16-13-42-28.txt" --start 1000 --frames 400 \
    --seed 1 --out "$seq" -q >"$out/radar_sim.log"
  (cd "$seq" && find . -type f | sort | xargs sha256sum) >"$out/oxford_sequence.sha256"
  for m in pw-ndt pcl-ndt pcl-icp; do
    "$bin/radar_odometry" --format oxford --sequence "$seq" --method "$m" --out "$out/oxford_$m.txt" -q >"$out/oxford_$m.log"
  done

  echo "[$id] the car's sensors, summaries, bags and real scans" >&2
  local nus=$data/nuscenes-mini-radar
  "$bin/radar_odometry" --format nuscenes --dataroot "$nus" --scene all --method pw-ndt --imu --wheels \
    --out "$out/car_pw-ndt_imu_wheels.txt" -q >"$out/car_imu_wheels.log"
  "$bin/radar_odometry" --format nuscenes --dataroot "$nus" --scene all --method wheel-gyro \
    --out "$out/car_wheel-gyro.txt" -q >"$out/car_wheel_gyro.log"
  "$bin/radar_odometry" --format nuscenes --dataroot "$nus" --scene scene-0103 --eval --metric all --json \
    --steps "$out/steps_nuscenes.raw.csv" -q >"$out/summary_nuscenes.raw.json"
  "$bin/radar_odometry" --format oxford --sequence "$data/oxford-radar-real" --eval --metric all --json \
    --steps "$out/steps_oxford_real.raw.csv" --out "$out/oxford_real.txt" -q >"$out/summary_oxford_real.raw.json"
  "$bin/radar_odometry" --format radiate --sequence "$data/radiate-tiny-foggy" --out "$out/radiate_real.txt" -q \
    >"$out/radiate_real.log"
  if [ -x "$bin/radar_nuscenes_to_bag" ]; then
    "$bin/radar_nuscenes_to_bag" --dataroot "$nus" --scene scene-0103 --out "$bld/bags" >"$out/to_bag.log"
    "$bin/radar_odometry" --format rosbag --bag "$bld/bags/scene-0103.bag" --sensors preset:nuscenes_ars408 --imu \
      --out "$out/rosbag_scene-0103_imu.txt" -q >"$out/rosbag.log"
    "$bin/radar_odometry" --format rosbag --bag "$data/ros-rio-ti-mmwave/ti_mmwave_rospkg_demo.bag" \
      --sensors preset:ti_iwr6843_rio --out "$out/rosbag_ti.txt" -q >"$out/rosbag_ti.log" || true
    "$bin/radar_scans_to_bag" --format oxford --sequence "$data/oxford-radar-real" --out "$bld/bags/oxford.bag" \
      >"$out/scans_to_bag.log"
    "$bin/radar_odometry" --format rosbag --bag "$bld/bags/oxford.bag" --sensors preset:navtech_oxford \
      --out "$out/rosbag_oxford.txt" -q >"$out/rosbag_oxford.log"
  fi
  rm -rf "$bld/boreas_seq"
  "$bin/radar_sim" --layout boreas --imu navigation --start 80 --frames 60 --out "$bld/boreas_seq" -q >"$out/boreas_sim.log"
  "$bin/radar_odometry" --format boreas --sequence "$bld/boreas_seq" --imu --out "$out/boreas_sim_imu.txt" -q \
    >"$out/boreas_imu.log"

  echo "[$id] paper tables" >&2
  local tables
  if [ -x "$bld/benchmarks/radar_paper_tables" ]; then tables=("$bld/benchmarks/radar_paper_tables")
  elif [ -x "$bin/radar_paper_tables" ]; then tables=("$bin/radar_paper_tables")  # before benchmarks/
  else tables=("$bin/radar_odometry" --table); fi
  "${tables[@]}" --format nuscenes --dataroot "$data/nuscenes-mini-radar" --json -q >"$out/table_nuscenes.raw.json"
  "${tables[@]}" --format oxford --sequence "$seq" --json -q >"$out/table_oxford.raw.json"
  touch "$out/.complete"
}

# A paper table as JSON without its wall-clock timings and the sequences' paths (which differ
# between builds), for comparison: strip_table RAW > OUT.
strip_table() {
  python3 - "$1" <<'PY'
import json, sys
timing = {"ms_per_cycle", "ms_per_cycle_by_stage", "match_ms_median", "front_end_ms_median"}
def strip(x):
    if isinstance(x, dict):
        return {k: strip(v) for k, v in x.items() if k not in timing}
    if isinstance(x, list):
        return [strip(v) for v in x]
    return x
doc = json.load(open(sys.argv[1]))
doc.pop("sequences", None)
print(json.dumps(strip(doc), indent=1, sort_keys=True))
PY
}

# A run's summary or steps without wall-clock timings (keys or columns named *_ms, wall_s, ...):
# strip_timings RAW > OUT.
strip_timings() {
  python3 - "$1" <<'PY'
import csv, io, json, re, sys
timed = re.compile(r"(^|_)ms($|_)|wall_s|per_second|real_time|latency")
text = open(sys.argv[1]).read()
if sys.argv[1].endswith(".csv"):
    rows = list(csv.reader(io.StringIO(text)))
    keep = [i for i, h in enumerate(rows[0]) if not timed.search(h)] if rows else []
    print("\n".join(",".join(r[i] for i in keep) for r in rows))
else:
    def strip(x):
        if isinstance(x, dict):
            return {k: strip(v) for k, v in x.items() if not timed.search(k)}
        if isinstance(x, list):
            return [strip(v) for v in x]
        return x
    print(json.dumps(strip(json.loads(text)), indent=1, sort_keys=True))
PY
}

base=$(export_rev "$1")
head=$(export_rev "${2:-HEAD}")
run_rev "$base"
run_rev "$head"

for id in "$base" "$head"; do
  for t in nuscenes oxford; do strip_table "$work/out-$id/table_$t.raw.json" >"$work/out-$id/table_$t.json"; done
  for f in summary_nuscenes.raw.json summary_oxford_real.raw.json steps_nuscenes.raw.csv steps_oxford_real.raw.csv; do
    strip_timings "$work/out-$id/$f" >"$work/out-$id/${f/.raw/}"
  done
done

status=0
compared=0
for f in demo_sequences.sha256 scanning_traj.txt automotive_traj.txt oxford_sequence.sha256 \
         oxford_pw-ndt.txt oxford_pcl-ndt.txt oxford_pcl-icp.txt table_nuscenes.json table_oxford.json \
         summary_nuscenes.json summary_oxford_real.json \
         steps_nuscenes.csv steps_oxford_real.csv oxford_real.txt radiate_real.txt boreas_sim_imu.txt \
         $(cd "$work/out-$base" && ls nuscenes_*.txt car_*.txt rosbag_*.txt 2>/dev/null); do
  compared=$((compared + 1))
  if cmp -s "$work/out-$base/$f" "$work/out-$head/$f"; then
    echo "identical  $f"
  else
    echo "DIFFERENT  $f"
    status=1
  fi
done
[ "$status" -eq 0 ] && echo "all $compared files identical (${base:0:7} vs ${head:0:7})" || echo "differences found (${base:0:7} vs ${head:0:7})"
exit "$status"
