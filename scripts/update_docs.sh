#!/usr/bin/env bash
# Writes the tables the docs hold that the apps print from the field tables, each between its
# markers "<!-- NAME -->" and "<!-- end of NAME -->": radar_odometry --list-options into
# docs/apps.md, radar_sim --list-settings --markdown into docs/simulator.md. The CTests
# apps_options_doc and sim_settings_doc check them.
#   scripts/update_docs.sh [BUILD_DIR]   (default build)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
write() {  # write DOC NAME COMMAND...
  local doc=$1 name=$2
  shift 2
  python3 - "$doc" "$name" "$("$@")" <<'PY'
import sys
path, name, table = sys.argv[1], sys.argv[2], sys.argv[3].rstrip("\n") + "\n"
start, end = "<!-- %s -->\n" % name, "<!-- end of %s -->" % name
text = open(path, encoding="utf-8").read()
a, b = text.index(start) + len(start), text.index(end)
open(path, "w", encoding="utf-8").write(text[:a] + table + text[b:])
PY
  echo "$doc: $name written"
}
write "$root/docs/apps.md" "radar_odometry --list-options" "$build/apps/radar_odometry" --list-options
write "$root/docs/simulator.md" "radar_sim --list-settings --markdown" "$build/apps/radar_sim" --list-settings --markdown
