#!/usr/bin/env bash
# The paper's validation (section 5.2): its comparison RVEs, the 0/90 NCF at 2x2 and the +-45 NCF at
# 3x3 elementary RVEs, through the five manufacturing stages (Table 3's parameters, the cards of
# examples/gen-*) with several seeds, measured with ncf-measure and pooled beside Tables 2 and 4.
# Usage: bash examples/validation/validate.sh OUT [SEED ...]          (default seeds: 1 2 3)
#   NCF_VALIDATE="ncf090 ncf45" (the fabrics), NCF_NP (ranks, default 2), NCF_LMP_ARGS as for
#   examples/manufacturing/run.sh (a departure from Table 3 given there is the user's to state).
# A run already complete in OUT (its release data and measurement exist) is not repeated, nor is
# one a guard of the stages stopped (no pass-through, doc/howto_manufacturing.md): its folder
# keeps the reason in 'stopped', the other runs go on, and the table lists it.
# About 20 minutes per fabric and seed on 2 cores. Writes OUT/validation.md.
set -eEuo pipefail
trap 'echo "[validate] stopped by a failing command (status $?), line $LINENO: $BASH_COMMAND"' ERR
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
out=$(mkdir -p "${1:?usage: validate.sh OUT [SEED ...]}" && cd "$1" && pwd)
shift
seeds=("$@")
[ ${#seeds[@]} -gt 0 ] || seeds=(1 2 3)
source "${NCF_BUILD:-$root/build}/ncf-env.sh"
export NCF_NP=${NCF_NP:-2}
declare -A rve=([ncf090]="2 2" [ncf45]="3 3")
for fab in ${NCF_VALIDATE:-ncf090 ncf45}; do
  [ -n "${rve[$fab]:-}" ] || { echo "validate.sh: unknown fabric '$fab' (ncf090, ncf45)"; exit 1; }
  for seed in "${seeds[@]}"; do
    dir="$out/$fab-seed$seed"
    if [ -s "$dir/measure/ncf-measure-summary.csv" ]; then
      echo "[validate] $fab seed $seed: done before ($dir)"
      continue
    fi
    if [ -s "$dir/stopped" ]; then
      echo "[validate] $fab seed $seed: stopped before ($dir/stopped; remove the folder to run it again)"
      continue
    fi
    t0=$SECONDS
    if ! NCF_RVE="${rve[$fab]}" NCF_SEED=$seed bash "$root/examples/manufacturing/run.sh" "$dir" "$fab"; then
      { grep -h "^ERROR" "$dir"/*.log 2>/dev/null | head -n 1 || true; } > "$dir/stopped"
      [ -s "$dir/stopped" ] || echo "run.sh failed without a LAMMPS error (see its output)" > "$dir/stopped"
      echo "[validate] $fab seed $seed: STOPPED, not measured: $(cat "$dir/stopped")"
      continue
    fi
    echo "$fab seed $seed rve ${rve[$fab]} wall_s $((SECONDS - t0)) ranks $NCF_NP" > "$dir/wall"
    /usr/bin/python3 "$root/examples/manufacturing/report_manufacturing.py" "$fab" --dir "$dir" \
      --out "$dir/manufacturing.md" > /dev/null ||
      echo "[validate] WARNING: a check of the manufacturing failed, see $dir/manufacturing.md"
    ncf-measure "$dir/$fab.release.data" --needles "$dir/$fab.needles" --summary "$dir/$fab.summary" \
      --out "$dir/measure" -q
  done
done
# Fig. 10: the orientation of every fabric's seeds measured together (densities averaged seed by
# seed, mean and SD from the pooled bonds), into OUT/FABRIC-pooled/ (a name that the runs'
# FABRIC-seed* does not match)
for fab in ncf090 ncf45; do
  files=() needles=()
  for d in "$out/$fab"-seed*; do
    [ -s "$d/measure/ncf-measure-summary.csv" ] || continue
    files+=("$d/$fab.release.data")
    needles+=(--needles "$d/$fab.needles")
    summary=$d/$fab.summary
  done
  [ ${#files[@]} -gt 1 ] || continue
  ncf-measure "${files[@]}" "${needles[@]}" --summary "$summary" --no-defects \
    --out "$out/$fab-pooled" -q
done
{
  echo "# Validation: the paper's comparison RVEs (generated $(date -u '+%Y-%m-%d %H:%M UTC'))"
  echo
  echo "| fabric | seed | RVE | nodes with the yarn | wall time | ranks | checks |"
  echo "|---|---|---|---|---|---|---|"
  args=()
  for fab in ncf090 ncf45; do
    csvs=()
    for d in "$out/$fab"-seed*; do
      if [ -s "$d/stopped" ]; then
        echo "| $fab | ${d##*seed} | – | – | – | – | stopped: $(cat "$d/stopped") |"
        continue
      fi
      [ -s "$d/measure/ncf-measure-summary.csv" ] || continue
      csvs+=("$d/measure/ncf-measure-summary.csv")
      read -r _ _ seed _ r1 r2 _ wall _ np < "$d/wall"
      nodes=$(grep 'total atoms' "$d/$fab.summary" | awk '{print $4}' | tr -d ,)
      checks=$(grep -q FAIL "$d/manufacturing.md" && echo "a check failed" || echo "all hold")
      echo "| $fab | $seed | $r1×$r2 | $nodes | $((wall / 60)) min $((wall % 60)) s | $np | $checks |"
    done
    [ ${#csvs[@]} -gt 0 ] && args+=("--$fab" "${csvs[@]}")
  done
  echo
  for fab in ncf090 ncf45; do
    [ -s "$out/$fab-pooled/ncf-measure.md" ] || continue
    echo "Orientation of $fab, all seeds (Fig. 10; $out/$fab-pooled/ncf-measure-orientation.png):"
    echo
    sed -n '/^| layer/,/^$/{p;/^$/q}' "$out/$fab-pooled/ncf-measure.md"
  done
  echo "All measurements of all seeds pooled (mean ± SD, number of measurements):"
  echo
  /usr/bin/python3 "$root/examples/manufacturing/compare_paper.py" "${args[@]}"
} > "$out/validation.md"
echo "[validate] $out/validation.md"
