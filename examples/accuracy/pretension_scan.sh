#!/usr/bin/env bash
# Where the loop tilt comes from (doc/accuracy_cost.md, "The loop tilt"): stage 4 (the pretension)
# run again from the stitched state of a finished run, for several damping times tau and shrink
# ramps (both in steps), each measured with ncf-measure right after the pretension's hold. Stages
# 1-3 are not repeated, so every point starts from the same stitched fabric; the release is left
# out (with the default holds it moves the loop tilt by less than 0.1 deg).
#
# Usage: bash examples/accuracy/pretension_scan.sh RUN OUT [TAU:RAMP ...]
#   RUN   a folder of examples/manufacturing/run.sh (or of study.sh) with PREFIX.stitch.restart
#   OUT   output folder: one folder per point and OUT/scan.csv
#   TAU:RAMP  damping time and shrink ramp in steps (default: 1000:10000 2000:10000 4000:10000
#         2000:40000 4000:40000 8000:40000; the scripts' defaults are 2000:10000)
#   NCF_SCAN_CARD  the fabric card of RUN (default: the one *.card in RUN, as study.sh leaves it)
# About 1 to 2.5 minutes per point for the +-45 elementary RVE on one core. A point already
# measured in OUT is not repeated.
set -eEuo pipefail
trap 'echo "[pretension-scan] stopped by a failing command (status $?), line $LINENO: $BASH_COMMAND"' ERR
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
run=$(cd "${1:?usage: pretension_scan.sh RUN OUT [TAU:RAMP ...]}" && pwd)
out=$(mkdir -p "${2:?usage: pretension_scan.sh RUN OUT [TAU:RAMP ...]}" && cd "$2" && pwd)
shift 2
points=("$@")
[ ${#points[@]} -gt 0 ] || points=(1000:10000 2000:10000 4000:10000 2000:40000 4000:40000 8000:40000)
: "${NCF_BUILD:=$root/build}"
export NCF_BUILD
source "$NCF_BUILD/ncf-env.sh"

cards=("$run"/*.card)
card=${NCF_SCAN_CARD:-${cards[0]}}
[ -f "$card" ] || { echo "pretension_scan.sh: no fabric card in $run (give it as NCF_SCAN_CARD)"; exit 1; }
prefix=$(awk '$1 == "name" { print $2; exit }' "$card")
[ -f "$run/$prefix.stitch.restart" ] || { echo "pretension_scan.sh: no $prefix.stitch.restart in $run"; exit 1; }

for p in "${points[@]}"; do
  [[ "$p" =~ ^([0-9]+):([0-9]+)$ ]] || { echo "pretension_scan.sh: point '$p' is not TAU:RAMP (steps)"; exit 1; }
  tau=${BASH_REMATCH[1]} ramp=${BASH_REMATCH[2]}
  d="$out/tau$tau-ramp$ramp"
  if [ -s "$d/measure/ncf-measure-summary.csv" ]; then
    echo "[pretension-scan] tau $tau ramp $ramp: done before ($d)"
    continue
  fi
  rm -rf "$d" && mkdir -p "$d"
  cp "$card" "$run/$prefix".{stitch.restart,settings.lmp,plates.lmp,yarn.lmp,needles,summary} "$d/"
  echo "[pretension-scan] tau $tau ramp $ramp: $(date -u '+%H:%M:%S')"
  /usr/bin/time -f "%e" -o "$d/time" env NCF_STAGES=4 NCF_LMP_ARGS="-var tau $tau" \
    NCF_ARGS_pretension="-var ramp $ramp" \
    bash "$root/examples/manufacturing/run.sh" "$d" "$d/$(basename "$card")" > "$d/run.out" 2>&1 ||
    { echo "[pretension-scan] tau $tau ramp $ramp FAILED: $d/run.out"; tail -5 "$d/run.out"; continue; }
  ncf-measure "$d/$prefix.pretension.data" --needles "$d/$prefix.needles" \
    --summary "$d/$prefix.summary" --out "$d/measure" -q
  rm -f "$d/$prefix.stitch.restart" "$d/$prefix.pretension.restart" "$d"/*.dump
done

# one line per point: tau, ramp, ramp/tau, loop tilt (mean, SD over the loops), orientation SD
# and crack length per layer, wall time
{
  echo "tau_steps,ramp_steps,ramp_over_tau,loop_tilt_deg,loop_tilt_sd_deg,orientation_sd_deg,crack_length_mm,wall_s"
  for d in "$out"/tau*-ramp*/; do
    s="$d/measure/ncf-measure-summary.csv"
    [ -s "$s" ] || continue
    [[ "$(basename "$d")" =~ ^tau([0-9]+)-ramp([0-9]+)$ ]]
    awk -F, -v tau="${BASH_REMATCH[1]}" -v ramp="${BASH_REMATCH[2]}" -v wall="$(cat "$d/time")" '
      $3 == "loop tilt from x (signed)" { tilt = $5; tsd = $6 }
      $3 == "orientation deviation SD" { osd = osd (osd == "" ? "" : " / ") sprintf("%.2f", $5) }
      $3 == "crack length" { cl = cl (cl == "" ? "" : " / ") sprintf("%.2f", $5) }
      END { printf "%d,%d,%.3g,%.3f,%.3f,%s,%s,%s\n", tau, ramp, ramp / tau, tilt, tsd, osd, cl, wall }' "$s"
  done | sort -t, -k3,3g -k1,1n
} > "$out/scan.csv"
column -s, -t "$out/scan.csv"
