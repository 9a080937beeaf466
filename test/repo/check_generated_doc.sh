#!/usr/bin/env bash
# A doc holds exactly what an app prints from the field tables, between the markers
# "<!-- NAME -->" and "<!-- end of NAME -->" (scripts/update_docs.sh writes it there).
# Usage: check_generated_doc.sh DOC NAME COMMAND...
set -u
doc=${1:?usage: check_generated_doc.sh DOC NAME COMMAND...}
name=${2:?usage: check_generated_doc.sh DOC NAME COMMAND...}
shift 2
in_doc=$(awk -v s="<!-- $name -->" -v e="<!-- end of $name -->" '$0 == e {on = 0} on {print} $0 == s {on = 1}' "$doc")
printed=$("$@")
if [ -z "$in_doc" ]; then
  echo "$doc has no table between <!-- $name --> and <!-- end of $name -->"
  exit 1
fi
if [ "$in_doc" != "$printed" ]; then
  echo "$doc's table differs from what '$name' prints (scripts/update_docs.sh writes it):"
  diff <(echo "$in_doc") <(echo "$printed") | head -20
  exit 1
fi
echo "$doc holds what '$name' prints ($(echo "$printed" | wc -l) lines)"
