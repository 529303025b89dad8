#!/usr/bin/env bash
# Long-run robustness of a stitched fabric (not part of the ctest suite: it runs for many minutes).
# The small +-45 fabric of examples/manufacturing (small.card, ~1 600 nodes) is made through stages
# 1-4 with the example test's short settings, then held (in.hold: plates, friction, averaged PBC,
# the full yarn shrink) for STEPS steps on 1, 2 and 4 MPI ranks. Checked: no lost atom or bond
# (thermo_modify lost error lost/bond error), the bond count unchanged, no NaN or inf in any thermo
# value, no pass-through (fix halt), and the end states of the rank counts against the 1-rank one.
# Then a SIGKILL: the 2-rank run again, killed once it has passed 55 % of the steps, restarted from
# the last restart file it wrote, run to the end and compared with the uninterrupted 2-rank run.
# Usage: bash tests/long/long_run.sh OUT [STEPS]       (STEPS default 1000000)
set -eEuo pipefail
trap 'echo "[long-run] stopped by a failing command (status $?), line $LINENO: $BASH_COMMAND"' ERR
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
man="$root/examples/manufacturing"
out=$(mkdir -p "${1:?usage: long_run.sh OUT [STEPS]}" && cd "$1" && pwd)
steps=${2:-1000000}
source "${NCF_BUILD:-$root/build}/ncf-env.sh"
every=$((steps / 100))
every_restart=$((steps / 10))
cd "$out"
short="-var hold 1000 -var release 1500 -var ramp 4000"
echo "[long-run] small fabric, stages 1-4 -> $out"
NCF_NP=2 NCF_STAGES=1-4 NCF_LMP_ARGS="$short" NCF_ARGS_pierce="-var hold 2000" \
  bash "$man/run.sh" "$out" "$man/small.card" >/dev/null
start=$(awk '/^PRETENSION step/ { print $3 }' small.pretension.log)
last=$((start + steps))
lmp_np() { local np=$1; shift; if [ "$np" -gt 1 ]; then mpirun -np "$np" --oversubscribe lmp "$@"; else lmp "$@"; fi; }
hold() {    # np out [extra lammps args]
  local np=$1 name=$2; shift 2
  local t0=$SECONDS
  lmp_np "$np" -in "$here/in.hold" -var prefix small -var here "$man" -var last "$last" -var ramp 4000 \
    -var every "$every" -var every_restart "$every_restart" -var out "$name" "$@" -log "$name.log" -screen none
  echo "[long-run] $name: $np rank(s), steps $start -> $last in $((SECONDS - t0)) s"
}
for np in 1 2 4; do
  hold "$np" "hold.np$np"
done
# SIGKILL in the middle of the 2-rank run
kill_at=$((start + steps * 55 / 100))
(lmp_np 2 -in "$here/in.hold" -var prefix small -var here "$man" -var last "$last" -var ramp 4000 \
  -var every "$every" -var every_restart "$every_restart" -var out hold.killed -log hold.killed.log -screen none) &
pid=$!
while kill -0 $pid 2>/dev/null; do
  s=$(awk '$1 ~ /^[0-9]+$/ && NF > 8 { s = $1 } END { print s + 0 }' hold.killed.log 2>/dev/null || echo 0)
  if [ "$s" -ge "$kill_at" ]; then
    pkill -KILL -P $pid || true; kill -KILL $pid 2>/dev/null || true
    pkill -KILL -f "out hold.killed" || true
    break
  fi
  sleep 1
done
wait $pid 2>/dev/null || true
echo "[long-run] hold.killed: killed with SIGKILL at step $s"
# the last restart file written before the last thermo line the killed run printed (a file being
# written at the kill would be incomplete)
restart=$(ls hold.killed.*.restart | sed 's/hold.killed.\([0-9]*\).restart/\1 &/' | sort -n |
  awk -v s="$s" '$1 < s { f = $2 } END { print f }')
[ -n "$restart" ] || { echo "[long-run] FAIL: no restart file of the killed run before step $s"; exit 1; }
echo "[long-run] restarting from $restart"
hold 2 hold.resumed -var from "$restart"
/usr/bin/python3 -B "$here/long_check.py" "$out" "$steps"
