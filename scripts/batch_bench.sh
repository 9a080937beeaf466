#!/usr/bin/env bash
# radar_batch's benchmark (docs/results/batch.md): eight simulated Oxford sequences of 500 scans
# (two stretches of each of four Oxford ground-truth drives) x two methods (ours, PCL's NDT), run
# serially, with GNU parallel -j 2 and through a local single-node Slurm (test/batch/local_slurm.py,
# needs root), each task on one thread. Prints wall times and speed-ups and checks that the three
# reports agree (all but the timing column).
# Usage: scripts/batch_bench.sh [BUILD_DIR] [WORK_DIR]      (defaults: build, /tmp/radar_batch_bench)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
work=${2:-/tmp/radar_batch_bench}
gt=$root/../shared/data/oxford-radar-gt
apps=$build/apps
mkdir -p "$work/seqs"
# The sequences (simulated once; kept between runs of this script).
i=0
for drive in 2019-01-10-11-46-21 2019-01-11-13-24-51 2019-01-15-12-01-32 2019-01-18-14-14-42; do
  for start in 2000 5000; do
    i=$((i + 1))
    out=$work/seqs/sim-$i-${drive:0:10}-$start
    [ -f "$out/radar.timestamps" ] || "$apps/radar_sim" --type scanning --trajectory "$gt/$drive.txt" \
      --start "$start" --frames 500 --seed "$i" --out "$out" -q
  done
done
seconds() { local t0 t1; t0=$(date +%s%N); "$@" > /dev/null; t1=$(date +%s%N); awk -v d=$((t1 - t0)) 'BEGIN { print d / 1e9 }'; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", a / b }'; }
for engine in serial parallel slurm; do
  rm -rf "$work/$engine"
  "$apps/radar_batch" plan --format oxford --root "$work/seqs" --method pw-ndt,pcl-ndt --out "$work/$engine" > /dev/null
done
serial=$(seconds "$apps/radar_batch" run "$work/serial" --engine serial --threads 1)
parallel=$(seconds "$apps/radar_batch" run "$work/parallel" --engine parallel -j 2 --threads 1)
slurm=""
if python3 -c "import sys; sys.path.insert(0, '$root/test/batch'); import local_slurm; sys.exit(1 if local_slurm.missing() else 0)"; then
  eval "$(python3 "$root/test/batch/local_slurm.py" start "$work/slurmd")"
  slurm=$(seconds "$apps/radar_batch" run "$work/slurm" --engine slurm --wait --throttle 2 --threads 1)
  python3 "$root/test/batch/local_slurm.py" stop "$work/slurmd"
fi
for engine in serial parallel slurm; do "$apps/radar_batch" report "$work/$engine" > /dev/null 2>&1 || true; done
strip() { cut -d, -f1-13,15- "$1"; }  # all but ms_per_scan (column 14)
same=yes
for engine in parallel slurm; do
  [ -f "$work/$engine/summary.csv" ] && grep -q complete "$work/$engine/summary.csv" || continue
  diff -q <(strip "$work/serial/summary.csv") <(strip "$work/$engine/summary.csv") > /dev/null || same=no
done
echo "| engine | wall s | speed-up |"
echo "|---|---|---|"
printf '| serial | %.1f | 1.00x |\n' "$serial"
printf '| GNU parallel -j 2 | %.1f | %.2fx |\n' "$parallel" "$(ratio "$serial" "$parallel")"
[ -n "$slurm" ] && printf '| local Slurm, --throttle 2 | %.1f | %.2fx |\n' "$slurm" "$(ratio "$serial" "$slurm")"
echo "reports agree (all but ms per scan): $same"
