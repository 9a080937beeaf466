#!/usr/bin/env bash
# docs/apps.md documents every option each app's --help lists. Usage: check_apps_doc.sh DOC APP...
set -u
doc=${1:?usage: check_apps_doc.sh DOC APP...}
shift
missing=0
for app in "$@"; do
  name=$(basename "$app")
  grep -q "## \`$name\`" "$doc" || { echo "$doc has no section for $name"; missing=$((missing + 1)); }
  for opt in $("$app" --help | grep -oE '^  (-[a-z], )?--[a-z0-9-]+' | grep -oE -- '--[a-z0-9-]+'); do
    grep -q -- "$opt" "$doc" || { echo "$name $opt is not in $doc"; missing=$((missing + 1)); }
  done
done
[ $missing -eq 0 ] && echo "every option of $# apps is in $doc"
[ $missing -eq 0 ]
