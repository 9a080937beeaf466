#!/usr/bin/env bash
# Every C++ source of the project is formatted as the repository's .clang-format says (clang-format
# --dry-run --Werror), so a badly formatted file fails the suite, and with it CI. Build folders
# inside the checkout are not sources. Usage: check_format.sh REPO_ROOT [CLANG_FORMAT]
# scripts/format.sh applies the format.
set -u
root=${1:?usage: check_format.sh REPO_ROOT [CLANG_FORMAT]}
tool=${2:-clang-format}
command -v "$tool" >/dev/null 2>&1 || { echo "check_format: $tool not found (.ci/deps installs Debian's clang-format)"; exit 1; }
[ -f "$root/.clang-format" ] || { echo "check_format: $root/.clang-format is missing"; exit 1; }
mapfile -d '' files < <(cd "$root" && find apps benchmarks core io python radar_ndt registration ros sim test \
  \( -name '*.cpp' -o -name '*.h' -o -name '*.hpp' \) -print0 | sort -z)
[ ${#files[@]} -gt 0 ] || { echo "check_format: no sources found under $root"; exit 1; }
bad=0
for f in "${files[@]}"; do
  if ! (cd "$root" && "$tool" --dry-run --Werror "$f" >/dev/null 2>&1); then
    echo "not formatted: $f (scripts/format.sh formats it; the first differences:)"
    (cd "$root" && "$tool" --dry-run "$f" 2>&1 | head -6)
    bad=$((bad + 1))
  fi
done
echo "check_format: ${#files[@]} sources checked with $("$tool" --version | head -1), $bad not formatted"
[ "$bad" -eq 0 ]
