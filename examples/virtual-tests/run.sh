#!/usr/bin/env bash
# The virtual tests of an as-manufactured fabric (doc/howto_virtual_tests.md): through-thickness
# compaction (in.compaction) and in-plane shear in both senses (in.shear), from the released
# fabric of the manufacturing stages, then the report (report_virtual_tests.py: curves, Toll's
# law, shear force, asymmetry).
#
# Usage: run.sh DIR PREFIX [PREFIX ...]
#   DIR     the folder of the manufacturing outputs (PREFIX.release.restart, PREFIX.settings.lmp,
#           PREFIX.summary); the tests write there too
#   PREFIX  a fabric's output prefix (its card's name: ncf45, ncf090, ...)
# Environment:
#   NCF_NP        MPI ranks (default 1)
#   NCF_VTESTS    which tests: "compaction shear" (default), or one of them
#   NCF_ANGLE     largest shear angle [deg] (default 40); both senses run
#   NCF_FRAME     bias or square; default from the layer angles in PREFIX.summary (+-45: bias,
#                 0/90: square)
#   NCF_VT_ARGS   extra LAMMPS arguments for every test, e.g. "-var rate 50 -var pmax 1e5"
#   NCF_ARGS_compaction, NCF_ARGS_shear   extra arguments for one test (they win: they come first)
set -eEuo pipefail
trap 'echo "[virtual-tests] run.sh: stopped by a failing command (status $?), line $LINENO: $BASH_COMMAND"' ERR
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
[ $# -ge 2 ] || { echo "usage: run.sh DIR PREFIX [PREFIX ...]"; exit 1; }
[ -d "$1" ] || { echo "run.sh: no folder '$1' (the manufacturing outputs)"; exit 1; }
dir=$(cd "$1" && pwd)
shift
: "${NCF_BUILD:=$here/../../build}"
source "$NCF_BUILD/ncf-env.sh"
np=${NCF_NP:-1}
angle=${NCF_ANGLE:-40}
tests=${NCF_VTESTS:-compaction shear}
for t in $tests; do
  [[ $t == compaction || $t == shear ]] ||
    { echo "run.sh: NCF_VTESTS='$tests': expected compaction and/or shear"; exit 1; }
done
[[ "$angle" =~ ^[0-9]+([.][0-9]+)?$ ]] ||
  { echo "run.sh: NCF_ANGLE='$angle': expected a positive angle in degrees (both senses run)"; exit 1; }

run_lmp() { if [ "$np" -gt 1 ]; then mpirun -np "$np" --oversubscribe lmp "$@"; else lmp "$@"; fi; }

one() {    # prefix name input-args...
  local p=$1 name=$2 t0=$SECONDS log="$1.$2.log"
  shift 2
  local extra="NCF_ARGS_${name%%-*}"
  # shellcheck disable=SC2086  (word splitting of the extra arguments is wanted)
  if ! run_lmp -var prefix "$p" -var here "$here" ${!extra:-} "$@" ${NCF_VT_ARGS:-} \
    -log "$log" -screen none; then
    echo "[virtual-tests] $p $name FAILED after $((SECONDS - t0)) s; the end of $dir/$log:"
    tail -15 "$log"
    return 1
  fi
  echo "[virtual-tests] $p $name done in $((SECONDS - t0)) s ($(grep -c . "$p.$name.dat") records)"
}

cd "$dir"
for p in "$@"; do
  for f in "$p.release.restart" "$p.settings.lmp" "$p.summary"; do
    [ -f "$f" ] || { echo "run.sh: no $dir/$f: run the manufacturing stages first (examples/manufacturing/run.sh)"; exit 1; }
  done
  frame=${NCF_FRAME:-}
  if [ -z "$frame" ]; then
    # the layer angles of the summary: all +-45 -> bias, all 0/90 -> square
    angles=$(awk '$1 == "nominal" && $2 == "angle," { print $4 }' "$p.summary" | tr '\n' ' ')
    frame=$(awk -v a="$angles" 'BEGIN { n = split(a, v, " "); b = 1; s = 1
      for (i = 1; i <= n; i++) { x = v[i] + 0; if (x != 45 && x != -45) b = 0
        if (x != 0 && x != 90 && x != -90) s = 0 }
      print (n > 0 && b) ? "bias" : ((n > 0 && s) ? "square" : "") }')
    [ -n "$frame" ] || { echo "run.sh: $p: layer angles '$angles' are neither +-45 nor 0/90: set NCF_FRAME=bias or square"; exit 1; }
  fi
  for t in $tests; do
    if [ "$t" = compaction ]; then
      one "$p" compaction -in "$here/in.compaction"
    else
      one "$p" shear-pos -in "$here/in.shear" -var frame "$frame" -var angle "$angle" -var out "$p.shear-pos"
      one "$p" shear-neg -in "$here/in.shear" -var frame "$frame" -var angle "-$angle" -var out "$p.shear-neg"
    fi
  done
done
/usr/bin/python3 -B "$here/report_virtual_tests.py" "$@" --dir "$dir" --out "$dir/virtual_tests.md"
