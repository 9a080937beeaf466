#!/usr/bin/env bash
# Long runs: does the scanning odometry keep its memory and its speed over a long drive? Simulates a
# 2,000-scan stretch of an Oxford drive (or takes SEQ), runs the odometry on its first 500 scans
# and on all of them, and prints the peak memory of each run and the median match ms a scan (one
# thread: --no-prefetch) of the first and the last quarter of the long run. Targets (the testing
# issue): peak memory within 10 % of the short run's, the last quarter's median within 10 % of the
# first quarter's. A standing vehicle matches faster than a moving one, so the default stretch
# (2019-01-18 from pose 5000) is one that moves in both quarters; and since the quarters still see
# different streets, the script also runs the last quarter's scans alone, from a fresh start, and
# compares the same scans: what a long run costs by itself. A benchmark, not a test: run it on a
# quiet machine (docs/testing.md).
#
# Usage: scripts/long_run.sh [SEQ]   (SEQ: an Oxford-layout sequence of at least 2,000 scans)
# Needs GNU time (/usr/bin/time, Debian package `time`) for the peak memory.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD_DIR:-build}
work=${LONG_RUN_DIR:-$build/long_run}
mkdir -p "$work"
seq=${1:-}
if [ -z "$seq" ]; then
  seq=$work/2019-01-18-from-5000
  if [ ! -f "$seq/radar.timestamps" ]; then
    "$build/apps/radar_sim" --type scanning --trajectory ../shared/data/oxford-radar-gt/2019-01-18-14-14-42.txt \
      --start 5000 --frames 2000 --out "$seq" -q
  fi
fi
[ -x /usr/bin/time ] || { echo "long_run: needs /usr/bin/time (apt-get install time)" >&2; exit 2; }
n=$(wc -l < "$seq/radar.timestamps")
[ "$n" -ge 2000 ] || { echo "long_run: $seq has $n scans, fewer than 2000" >&2; exit 2; }

run() {  # scans tag [first scan]
  /usr/bin/time -f "%M" -o "$work/$2.rss" "$build/apps/radar_odometry" --format oxford --sequence "$seq" \
    --start "${3:-0}" --max-cycles "$1" --no-prefetch --steps "$work/$2.csv" -q >/dev/null
}
run 500 short
run 2000 long
run 501 fresh 1499
python3 - "$work" <<'EOF'
import csv, statistics, sys
work = sys.argv[1]
rss = {t: int(open(f"{work}/{t}.rss").read().split()[-1]) for t in ("short", "long")}
rows = list(csv.DictReader(open(f"{work}/long.csv")))
ms = [float(r["match_ms"]) for r in rows[1:]]
q = len(ms) // 4
first, last = statistics.median(ms[:q]), statistics.median(ms[-q:])
print(f"peak memory: 500 scans {rss['short'] / 1024:.1f} MiB, 2000 scans {rss['long'] / 1024:.1f} MiB "
      f"({100 * (rss['long'] / rss['short'] - 1):+.1f} %; target within 10 %)")
speed = lambda r: (float(r["dx"]) ** 2 + float(r["dy"]) ** 2) ** 0.5
print(f"match ms a scan (median): first quarter {first:.2f}, last quarter {last:.2f} "
      f"({100 * (last / first - 1):+.1f} %; target within 10 %); median step "
      f"{statistics.median(map(speed, rows[1:q + 1])):.2f} m and {statistics.median(map(speed, rows[-q:])):.2f} m")
# The same scans in a fresh run (its first scan only starts the map).
fresh = {r["timestamp_us"]: float(r["match_ms"]) for r in list(csv.DictReader(open(f"{work}/fresh.csv")))[1:]}
common = [r["timestamp_us"] for r in rows[-q:] if r["timestamp_us"] in fresh]
late = statistics.median(float(r["match_ms"]) for r in rows[-q:] if r["timestamp_us"] in fresh)
alone = statistics.median(fresh[t] for t in common)
print(f"the last quarter's {len(common)} scans: {late:.2f} ms after {len(rows) - q} scans, {alone:.2f} ms "
      f"from a fresh start ({100 * (late / alone - 1):+.1f} %)")
EOF
