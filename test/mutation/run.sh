#!/usr/bin/env bash
# Mutation testing: does the suite catch broken algorithms? Applies each mutation of
# test/mutation/mutations.txt (or only the IDs given) to a scratch copy of the sources, rebuilds
# what it touches, runs the suite, and prints a table: mutation, killed or survived, by which tests.
# A mutation killed only by tests that compare two runs with each other (determinism, and a faulty
# run against its clean twin), not with a value the mutation changes, counts as survived. Not part
# of CI (about an hour on 2 cores: one incremental build and one suite run per mutation); see
# docs/testing.md.
#
# Usage: test/mutation/run.sh [ID...]        e.g. test/mutation/run.sh M04 M15
# Environment: MUTATION_DIR (default build-mutation), MUTATION_JOBS (ctest -j, default 2).
set -uo pipefail
cd "$(dirname "$0")/../.."
root=$PWD
out=${MUTATION_DIR:-build-mutation}
jobs=${MUTATION_JOBS:-2}
list=test/mutation/mutations.txt
# Tests that compare two runs of the same code with each other (determinism; a run with faults
# against the clean run): they fail for any change of behaviour, so a kill by these alone is not one.
comparisons='Determinis|BitIdentical|ByteIdentical|SameFiles|Reproducible|ScanningFaults\.|FaultsCostOnlyTheirNeighbourhood'

mkdir -p "$out"
src=$out/src
bld=$out/build
# A scratch copy of the sources (tracked and untracked files git does not ignore, so the working
# tree's changes are tested), built once. Only files whose content differs are copied, with a new
# time: a second run rebuilds only what changed, and a mutation left behind by an interrupted run
# is overwritten and rebuilt (copying with the original times would hide it from the build).
mkdir -p "$src"
git ls-files -co --exclude-standard | grep -v "^$out/" | while IFS= read -r f; do
  [ -f "$f" ] || continue
  cmp -s "$f" "$src/$f" || { mkdir -p "$src/$(dirname "$f")" && cp "$f" "$src/$f"; }
done
# The real data the suite reads from ../shared/data beside its source tree.
[ -e "$out/shared" ] || ln -s "$(cd .. && pwd)/shared" "$out/shared"
if ! { cmake -S "$src" -B "$bld" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null && cmake --build "$bld" >/dev/null; }; then
  echo "mutation: the unmutated copy does not build" >&2
  exit 2
fi
# The repository checks (label "repository": formatting, the mutation list itself, the docs' paths)
# read the sources, which a mutation changes on purpose; they are left out here.
if ! ctest --test-dir "$bld" -j"$jobs" -LE repository >"$out/baseline.log" 2>&1; then
  echo "mutation: the unmutated suite fails (see $out/baseline.log): nothing to measure against" >&2
  exit 2
fi

# Applies (or, with "revert", undoes) one mutation's replacements to the scratch copy. Every OLD
# text must occur exactly once in its file, and every NEW text once after the change.
apply() {  # apply|revert ID
  python3 test/mutation/mutations.py "$1" "$2" "$list" "$src"
}

ids=("$@")
if [ ${#ids[@]} -eq 0 ]; then mapfile -t ids < <(grep -oP '^## \K\S+' "$list"); fi
printf '| mutation | what it breaks | result | killed by |\n|---|---|---|---|\n' >"$out/results.md"
start=$(date +%s)
for id in "${ids[@]}"; do
  what=$(grep -P "^## $id " "$list" | sed "s/^## $id //")
  t0=$(date +%s)
  if ! apply apply "$id"; then
    printf '| %s | %s | NOT APPLIED | - |\n' "$id" "$what" | tee -a "$out/results.md"
    continue
  fi
  result="survived"
  killers="-"
  if ! cmake --build "$bld" >"$out/$id.build.log" 2>&1; then
    result="killed"
    killers="(does not compile)"
  else
    ctest --test-dir "$bld" -j"$jobs" -LE repository --timeout 900 --output-on-failure >"$out/$id.ctest.log" 2>&1
    # The failed tests: CTest's names, and inside a binary that runs a whole suite (integration/)
    # the GoogleTest cases that failed, so a determinism case is told from a value check.
    failed=$( { grep -oP '^\[  FAILED  \] \K[A-Za-z0-9_/]+\.[A-Za-z0-9_/.]+' "$out/$id.ctest.log";
                grep -oP '^\s*\d+ - \K\S+(?= \()' "$out/$id.ctest.log" | grep -v '^test_.*' ; } | sort -u | tr '\n' ' ')
    # A binary that failed without a GoogleTest case failing (a crash, a timeout) counts by its name.
    for bin in $(grep -oP '^\s*\d+ - \K\S+(?= \()' "$out/$id.ctest.log" | grep '^test_' | sort -u); do
      grep -q "^\[  FAILED  \]" "$out/$id.ctest.log" || failed="$failed$bin "
    done
    if [ -n "$failed" ]; then
      value=$(echo "$failed" | tr ' ' '\n' | grep -v '^$' | grep -Ev "$comparisons" | tr '\n' ' ')
      if [ -n "$value" ]; then
        result="killed"
        killers=$value
      else
        result="survived (run comparisons only)"
        killers=$failed
      fi
    fi
  fi
  apply revert "$id" || { echo "mutation: could not revert $id" >&2; exit 2; }
  printf '| %s | %s | %s | %s |\n' "$id" "$what" "$result ($(($(date +%s) - t0)) s)" "$killers" | tee -a "$out/results.md"
done
cmake --build "$bld" >/dev/null 2>&1  # leave the copy built unmutated
survived=$(grep -c '| survived' "$out/results.md")
echo "mutation: ${#ids[@]} mutations in $(($(date +%s) - start)) s, $survived survived; table in $out/results.md"
[ "$survived" -eq 0 ]
