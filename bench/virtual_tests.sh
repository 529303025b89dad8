#!/bin/bash
# The time of the virtual tests (examples/virtual-tests, doc/howto_virtual_tests.md) on released
# fabrics: for each fabric, the compaction (to pmax and back) and the shear in both senses, at the
# default speeds and at the main job's short ones, timed in one run. Prints per test the steps,
# the wall time, the time per node-step, and the ratio of the defaults to the short version.
# Usage: bench/virtual_tests.sh DIR PREFIX [PREFIX ...]
#   DIR: manufacturing outputs with PREFIX.release.restart (examples/manufacturing/run.sh)
# NCF_NP (default 2) ranks; NCF_ANGLE (default 40) the shear angle of the default version (the short
# one shears to 20 deg); NCF_BENCH_KEEP=1 keeps the test outputs.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
source "$here/common.sh"
[ $# -ge 2 ] || { echo "usage: bench/virtual_tests.sh DIR PREFIX [PREFIX ...]"; exit 1; }
dir=$(cd "$1" && pwd)
shift
np=${NCF_NP:-2}
angle=${NCF_ANGLE:-40}
bench_work virtual-tests
vt=$root/examples/virtual-tests
run_lmp() { if [ "$np" -gt 1 ]; then mpirun -np "$np" --oversubscribe lmp "$@"; else lmp "$@"; fi; }
timed() {    # label prefix nodes args...
  local label=$1 p=$2 nodes=$3 t0 t1 steps
  shift 3
  t0=$(date +%s.%N)
  (cd "$work" && run_lmp -var prefix "$p" -var here "$vt" -screen none -log "$label.log" "$@")
  t1=$(date +%s.%N)
  steps=$(awk '/^Loop time of/ { s += $9 } END { print s + 0 }' "$work/$label.log")
  awk -v l="$label" -v t0="$t0" -v t1="$t1" -v s="$steps" -v n="$nodes" 'BEGIN {
    t = t1 - t0; printf "  %-28s %8d steps %8.1f s  %8.3g us per node-step\n", l, s, t, 1e6 * t / (s * n) }'
  echo "$label $(awk -v t0="$t0" -v t1="$t1" 'BEGIN { print t1 - t0 }')" >> "$work/times"
}
echo "$np rank(s); default: compaction vdrag 0.01, shear to $angle deg at 1000 steps/deg; short (main job): vdrag 0.05, 20 deg at 300 steps/deg"
for p in "$@"; do
  for f in "$dir/$p".*; do ln -sf "$f" "$work/"; done
  nodes=$(awk '$2 == "atoms" { print $1; exit }' "$dir/$p.release.data")
  frame=bias
  awk '$1 == "nominal" && $2 == "angle," { print $4 }' "$dir/$p.summary" | grep -qvE '^-?45$' && frame=square
  echo "$p: $nodes nodes, frame $frame"
  timed "$p.compaction" "$p" "$nodes" -in "$vt/in.compaction" -var out "$p.c"
  timed "$p.compaction-short" "$p" "$nodes" -in "$vt/in.compaction" -var vdrag 0.05 -var out "$p.cs"
  for s in 1 -1; do
    timed "$p.shear$s" "$p" "$nodes" -in "$vt/in.shear" -var frame $frame -var angle $((s * angle)) -var out "$p.s$s"
    timed "$p.shear-short$s" "$p" "$nodes" -in "$vt/in.shear" -var frame $frame -var angle $((s * 20)) \
      -var dseg 2 -var degsteps 300 -var out "$p.ss$s"
  done
  awk -v p="$p" '$1 == p ".compaction" { c = $2 } $1 == p ".compaction-short" { cs = $2 }
    $1 ~ "^" p ".shear-?1$" { s += $2 } $1 ~ "^" p ".shear-short" { ss += $2 }
    END { printf "  %s: default / short wall time: compaction %.2f, shear (both senses) %.2f\n", p, c / cs, s / ss }' "$work/times"
done
