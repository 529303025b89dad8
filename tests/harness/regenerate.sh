#!/usr/bin/env bash
# Regenerates the reference values of the harness YAML files (tests/harness/*.yaml) with the
# harness's -g mode, against the LAMMPS and plugin of a build folder; keeps each file's leading
# comment lines. Only for an intended change of a style's results; review the diff.
#   NCF_BUILD=build bash tests/harness/regenerate.sh [file.yaml ...]
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
build=${NCF_BUILD:-$here/../../build}
build=$(cd "$build" && pwd)
export LAMMPS_PLUGIN_PATH=$build
work=$build/tests/harness/regenerate
mkdir -p "$work"
files=("$@")
[ ${#files[@]} -gt 0 ] || files=("$here"/*.yaml)
for yaml in "${files[@]}"; do
  yaml=$(cd "$(dirname "$yaml")" && pwd)/$(basename "$yaml")
  name=$(basename "$yaml" .yaml)
  kind=${name%%-*}
  exe=$build/tests/harness/ncf_test_${kind}_style
  (cd "$work" && "$exe" "$yaml" -g "$work/$name.yaml" >"$work/$name.log" 2>&1) ||
    { cat "$work/$name.log" >&2; echo "regenerating $name failed" >&2; exit 1; }
  { sed -n '/^#/!q;p' "$yaml"; cat "$work/$name.yaml"; } >"$work/$name.new"
  mv "$work/$name.new" "$yaml"
  echo "regenerated $yaml"
done
