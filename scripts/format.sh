#!/usr/bin/env bash
# Formats every C++ source of the project in place with the repository's .clang-format (the CTest
# clang_format checks the same files). Usage: scripts/format.sh [CLANG_FORMAT]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
tool=${1:-clang-format}
cd "$root"
find apps benchmarks core io python radar_ndt registration ros sim test \( -name '*.cpp' -o -name '*.h' -o -name '*.hpp' \) -print0 | xargs -0 "$tool" -i
