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
#     `radar_odometry --format oxford --out` on that sequence for ours, PCL's NDT and PCL's ICP.
# Exit code 0 when every file is identical, 1 otherwise (each difference is listed).
set -euo pipefail

if [ $# -lt 1 ] || [ "$1" = "-h" ] || [ "$1" = "--help" ]; then
  sed -n '2,18p' "$0" | sed 's/^# \{0,1\}//'
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

  echo "[$id] paper tables" >&2
  local tables
  if [ -x "$bin/radar_paper_tables" ]; then tables=("$bin/radar_paper_tables"); else tables=("$bin/radar_odometry" --table); fi
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

base=$(export_rev "$1")
head=$(export_rev "${2:-HEAD}")
run_rev "$base"
run_rev "$head"

for id in "$base" "$head"; do
  for t in nuscenes oxford; do strip_table "$work/out-$id/table_$t.raw.json" >"$work/out-$id/table_$t.json"; done
done

status=0
compared=0
for f in demo_sequences.sha256 scanning_traj.txt automotive_traj.txt oxford_sequence.sha256 \
         oxford_pw-ndt.txt oxford_pcl-ndt.txt oxford_pcl-icp.txt table_nuscenes.json table_oxford.json \
         $(cd "$work/out-$base" && ls nuscenes_*.txt); do
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
