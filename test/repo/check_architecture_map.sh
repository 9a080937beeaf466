#!/usr/bin/env bash
# Every file or folder docs/architecture.md names (a `path/with/slash.ext` or `folder/` in
# backticks) exists, so the map cannot drift from the code. Paths are tried from the repository
# root and from each target's include folder (the map writes `frontend/ego_velocity.h` for
# radar_ndt/include/radar_ndt/frontend/ego_velocity.h). Also: no M_PI (not standard C++) in the
# sources; every dated note in docs/notes/ is linked from a doc, and every note a doc names exists.
# Usage: check_architecture_map.sh REPO_ROOT
set -u
root=${1:?usage: check_architecture_map.sh REPO_ROOT}
map=$root/docs/architecture.md
[ -f "$map" ] || { echo "missing: $map"; exit 1; }
prefixes=("" "radar_ndt/include/radar_ndt/" "core/include/radar_ndt/" "sim/include/radar_ndt/" "registration/include/radar_ndt/registration/"
          "io/include/radar_ndt/io/" "radar_ndt/")
missing=0 checked=0
while IFS= read -r path; do
  case "$path" in ../*) continue ;; esac
  checked=$((checked + 1))
  found=0
  for p in "${prefixes[@]}"; do
    if [ -e "$root/$p$path" ]; then found=1; break; fi
  done
  if [ $found -eq 0 ]; then
    echo "docs/architecture.md names '$path', which does not exist"
    missing=$((missing + 1))
  fi
done < <(grep -o '`[A-Za-z0-9_./-]*/[A-Za-z0-9_./-]*`' "$map" | tr -d '`' | grep -E '(\.(h|hpp|cpp|md|sh|cmake|in|txt|py)|/)$' | sort -u)
echo "docs/architecture.md: $checked paths checked, $missing missing"
uses=$(grep -rlw 'M_PI' --include='*.h' --include='*.hpp' --include='*.cpp' "$root/radar_ndt" "$root/registration" "$root/io" "$root/apps" "$root/test" 2>/dev/null)
if [ -n "$uses" ]; then
  echo "M_PI (not standard C++; use radar_ndt::kPi) in: $uses"
  missing=$((missing + 1))
fi
# Every dated note is linked from a doc outside docs/notes/ (or the README), and every note a doc
# names exists: a note nobody links to belongs folded into a pipeline doc.
for note in "$root"/docs/notes/*.md; do
  [ -e "$note" ] || continue
  name=$(basename "$note")
  if ! grep -rqF "docs/notes/$name" "$root/README.md" "$root/docs" --include='*.md' --exclude-dir=notes; then
    echo "docs/notes/$name is linked from no doc (fold it into a pipeline doc's 'Measured and not adopted')"
    missing=$((missing + 1))
  fi
done
for named in $(grep -rhoE 'docs/notes/[A-Za-z0-9_.-]+\.md' "$root/README.md" "$root/docs" --include='*.md' | sort -u); do
  [ -e "$root/$named" ] || { echo "$named is named in the docs but does not exist"; missing=$((missing + 1)); }
done
[ $checked -gt 20 ] || { echo "too few paths found in the map: the check itself is broken"; exit 1; }
[ $missing -eq 0 ]
