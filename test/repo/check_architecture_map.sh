#!/usr/bin/env bash
# Every file or folder docs/architecture.md names (a `path/with/slash.ext` or `folder/` in
# backticks) exists, so the map cannot drift from the code. Paths are tried from the repository
# root and from each target's include folder (the map writes `frontend/ego_velocity.h` for
# radar_ndt/include/radar_ndt/frontend/ego_velocity.h). Also: no M_PI (not standard C++) in the
# sources; no dated notes (docs/notes/ empty or gone, named by no doc); README at most 150 lines.
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
uses=$(grep -rlw 'M_PI' --include='*.h' --include='*.hpp' --include='*.cpp' "$root/radar_ndt" "$root/registration" "$root/io" "$root/apps" "$root/benchmarks" "$root/test" 2>/dev/null)
if [ -n "$uses" ]; then
  echo "M_PI (not standard C++; use radar_ndt::kPi) in: $uses"
  missing=$((missing + 1))
fi
# No dated notes: what was measured and not adopted lives in each pipeline doc's section of that
# name (git keeps the history), and no doc names a note.
if [ -d "$root/docs/notes" ] && [ -n "$(ls -A "$root/docs/notes" 2>/dev/null)" ]; then
  echo "docs/notes/ holds dated notes: fold them into a pipeline doc's 'Measured and not adopted'"
  missing=$((missing + 1))
fi
if grep -rqE 'docs/notes/' "$root/README.md" "$root/docs" --include='*.md'; then
  echo "a doc names docs/notes/: $(grep -rlE 'docs/notes/' "$root/README.md" "$root/docs" --include='*.md' | tr '\n' ' ')"
  missing=$((missing + 1))
fi
# README is the user's manual: at most 150 lines.
if [ "$(wc -l < "$root/README.md")" -gt 150 ]; then
  echo "README.md has $(wc -l < "$root/README.md") lines, more than 150 (the rest belongs in docs/)"
  missing=$((missing + 1))
fi
[ $checked -gt 20 ] || { echo "too few paths found in the map: the check itself is broken"; exit 1; }
[ $missing -eq 0 ]
