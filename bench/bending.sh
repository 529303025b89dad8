#!/bin/bash
# The per-step cost of the opt-in chain bending (ncf-gen 'bending bundle', issue 35): a mat
# compacted to the layer thickness with its chains' angles (stage 1 of examples/manufacturing on a
# card with 'bending bundle' added), timed from its restart file (bench/in.effects) with the
# angles (angle_style cosine, K = EI / l0) and with the angle style switched off (angle_style
# none: the same configuration, neighbour lists, contacts, plates and averaged PBC), the two
# variants interleaved in one run. Prints per variant the CPU time per node-step of the whole
# step, of the bonded terms (LAMMPS "Bond" section: bonds and angles) and of the pair, and the
# ratio with / without bending.
# Usage: bench/bending.sh [steps]    (after tools/setup.sh; uses build/ncf-env.sh)
# NCF_BENCH_CARD (default examples/gen-ncf45/ncf45.card, the +-45 elementary RVE),
# NCF_BENCH_REPS (default 3) repetitions, NCF_BENCH_FROZEN="1 0" (default): 1 the same
# configuration every step (no time integration), 0 moving under the forces (with bending the mat
# moves differently); NCF_BENCH_SCENE=DIR an earlier compaction of a bending card (its
# PREFIX.compact.restart and generator files) instead of compacting first (untimed, about a
# minute on one idle core for the +-45 RVE); NCF_BENCH_KEEP=1 keeps the logs.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
source "$here/common.sh"
steps=${1:-500}
reps=${NCF_BENCH_REPS:-3}
card=${NCF_BENCH_CARD:-$root/examples/gen-ncf45/ncf45.card}
bench_work bending
if [ -n "${NCF_BENCH_SCENE:-}" ]; then
  scene=$(cd "$NCF_BENCH_SCENE" && pwd)
else
  scene=$work/scene
  mkdir -p "$scene"
  # the card with its materials file made absolute (the copy lives elsewhere) and bending on
  carddir=$(cd "$(dirname "$card")" && pwd)
  awk -v d="$carddir" '$1 == "materials" && $2 !~ /^\// { $2 = d "/" $2 } $1 != "bending" { print }
    END { print "bending bundle" }' "$card" > "$work/bending.card"
  echo "stage 1 of $(basename "$card") with 'bending bundle' (untimed) ..."
  NCF_STAGES=1 bash "$man/run.sh" "$scene" "$work/bending.card" > "$work/stage1.out"
fi
prefix=$(basename "$(ls "$scene"/*.compact.restart | head -1)" .compact.restart)
grep -q '^angle_style cosine' "$scene/$prefix.settings.lmp" ||
  { echo "bending.sh: $scene/$prefix.settings.lmp has no angle_style cosine: not a bending card"; exit 1; }
for f in "$scene/$prefix".*; do ln -sf "$f" "$work/"; done
cd "$work"
sed 's/ mu [^ ]*/ mu ${mu}/' "$prefix.plates.lmp" > plates_mu.lmp

variants=("with bending (angle_style cosine)|on" "without bending (angle_style none)|off")
for frozen in ${NCF_BENCH_FROZEN:-1 0}; do
  for r in $(seq "$reps"); do
    for k in "${!variants[@]}"; do
      IFS='|' read -r _ b <<< "${variants[k]}"
      lmp -in "$here/in.effects" -var prefix "$prefix" -var here "$man" -var restart compact \
        -var steps "$steps" -var frozen "$frozen" -var bending "$b" -log "v$k.f$frozen.r$r.log" \
        -screen none
    done
  done
done

/usr/bin/env python3 - "$steps" "$reps" "${NCF_BENCH_FROZEN:-1 0}" "${variants[@]}" <<'PY'
import re, sys
steps, reps = int(sys.argv[1]), int(sys.argv[2])
modes = sys.argv[3].split()
variants = [v.split("|") for v in sys.argv[4:]]

def read(path):
    """the timed run (the last of the log): loop time, CPU share, sections, angles"""
    d = {"loop": 0.0, "cpu": 1.0, "Pair": 0.0, "Bond": 0.0, "angles": 0}
    for line in open(path):
        m = re.match(r"Loop time of ([0-9.eE+-]+) on \d+ procs for (\d+) steps with (\d+) atoms", line)
        if m:
            d["loop"], d["steps"], d["nodes"] = float(m.group(1)), int(m.group(2)), int(m.group(3))
        m = re.match(r"([0-9.]+)% CPU use", line)
        if m:
            d["cpu"] = float(m.group(1)) / 100.0
        m = re.match(r"(Pair|Bond) +\| +[0-9.eE+-]+ +\| +([0-9.eE+-]+)", line)
        if m:
            d[m.group(1)] = float(m.group(2))
        m = re.match(r"\s+(\d+) angles$", line)
        if m:
            d["angles"] = int(m.group(1))
    return d

# CPU time (loop time x LAMMPS's "CPU use"): on a shared machine a run waits for a core for a
# varying share of its wall time
per = lambda d, key="loop": 1e6 * d[key] * d["cpu"] / (d["nodes"] * d["steps"])
for frozen in modes:
    what = "same configuration every step" if frozen == "1" else "moving as in the stage"
    print(f"\n{steps} steps, {what}; CPU time per node-step in us (least of {reps})")
    print("| variant | nodes | angles | step | bonded (bonds + angles) | pair | ratio | ratio per repetition |")
    print("|---|---|---|---|---|---|---|---|")
    runs = [[read(f"v{k}.f{frozen}.r{r}.log") for r in range(1, reps + 1)] for k in range(len(variants))]
    base = min(runs[1], key=per)
    for k, (name, _) in enumerate(variants):
        best = min(runs[k], key=per)
        each = ", ".join(f"{per(a) / per(b):.3f}" for a, b in zip(runs[k], runs[1]))
        print(f"| {name} | {best['nodes']} | {best['angles']} | {per(best):.4f} | {per(best, 'Bond'):.4f} | "
              f"{per(best, 'Pair'):.4f} | {per(best) / per(base):.3f} | {each} |")
PY
