#!/bin/bash
# The cost of each effect of a manufacturing step (issue 16, item 4: "simulate only what the scene
# calls for"): a stage's state (examples/manufacturing, the +-45 elementary RVE by default) timed
# with one effect switched at a time (bench/in.effects), against the same state with the stage's
# own effects, in one run:
#   friction      mu 0.3 (contacts and plates) -> mu 0
#   fatom         the per-node contact force every 250 steps (the stages') -> every step
#   averaged PBC  fix ncf/pbc on the chain ends -> plain periodic box
#   needles       none -> through the mat / parked just above it (both stage 2)
#   plates        touching (stage 1-4) -> lifted out of reach / none (after the release)
#   yarn          the stitched state with its stitching yarn -> the yarn deleted
# Prints per variant the whole step, pair, fixes (LAMMPS "Modify") and communication cost per
# node-step, the ratio of the whole step to its baseline (fastest repetition, and every
# repetition's), the list builds, and what the variant did (contacts, needle segment visits).
# Usage: bench/effects.sh [steps]    (after tools/setup.sh; uses build/ncf-env.sh)
# NCF_BENCH_REPS (default 3) interleaved repetitions; NCF_BENCH_FROZEN="1 0" (default): 1 every
# step on the same configuration (no time integration: the cost of the effect alone), 0 the
# configuration moving under the forces as in the stage (the effect also changes the motion and
# the list builds); NCF_BENCH_NP (default 1) ranks; NCF_BENCH_FABRIC (default ncf45) card;
# NCF_BENCH_SCENE=DIR reuses the stage outputs of an earlier run (PREFIX.pierce.restart,
# PREFIX.stitch.restart and the generator's files, e.g. from examples/manufacturing/run.sh)
# instead of running stages 1-3 first (about 2 minutes on one idle core, untimed);
# NCF_BENCH_KEEP=1 keeps the logs (folder printed).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
source "$here/common.sh"
steps=${1:-500}
reps=${NCF_BENCH_REPS:-3}
np=${NCF_BENCH_NP:-1}
fab=${NCF_BENCH_FABRIC:-ncf45}
bench_work effects
bench_scene "$fab"
prefix=$(basename "$(ls "$scene"/*.pierce.restart | head -1)" .pierce.restart)
for f in "$scene/$prefix".*; do ln -sf "$f" "$work/"; done
cd "$work"
# the stage's plates with the friction coefficient of the variant (in.effects, variable mu)
sed 's/ mu [^ ]*/ mu ${mu}/' "$prefix.plates.lmp" > plates_mu.lmp

lmprun() { if [ "$np" -gt 1 ]; then mpirun -np "$np" --oversubscribe lmp "$@"; else lmp "$@"; fi; }
# name | restart | variables; the first of each restart is its baseline
variants=(
  "stage 2 state: plates, averaged PBC, mu 0.3|pierce|"
  "friction off (mu 0)|pierce|-var mu 0"
  "per-node contact force every step (fatom 1)|pierce|-var every 1"
  "plain periodic (no fix ncf/pbc)|pierce|-var pbc 0"
  "needles through the mat|pierce|-var needles in"
  "needles parked above the mat|pierce|-var needles out"
  "plates lifted out of reach|pierce|-var plates lifted"
  "no plates|pierce|-var plates none"
  "stage 3 state: with the yarn|stitch|"
  "yarn deleted|stitch|-var yarn 0"
)
for frozen in ${NCF_BENCH_FROZEN:-1 0}; do
  for r in $(seq "$reps"); do
    for k in "${!variants[@]}"; do
      IFS='|' read -r _ rs args <<< "${variants[k]}"
      # shellcheck disable=SC2086  (the variables are words)
      lmprun -in "$here/in.effects" -var prefix "$prefix" -var here "$man" -var restart "$rs" \
        -var steps "$steps" -var frozen "$frozen" $args -log "v$k.f$frozen.r$r.log" -screen none
    done
  done
done

/usr/bin/env python3 - "$steps" "$reps" "$np" "${NCF_BENCH_FROZEN:-1 0}" "${variants[@]}" <<'PY'
import re, sys
steps, reps, np = int(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3])
modes = sys.argv[4].split()
variants = [v.split("|") for v in sys.argv[5:]]

def read(path):
    """the timed run (the last of the log): loop time, its CPU share, sections, builds, ghosts"""
    d = {"loop": 0.0, "cpu": 1.0, "Pair": 0.0, "Modify": 0.0, "Comm": 0.0, "builds": 0}
    for line in open(path):
        m = re.match(r"Loop time of ([0-9.eE+-]+) on \d+ procs for (\d+) steps with (\d+) atoms", line)
        if m:
            d["loop"], d["steps"], d["nodes"] = float(m.group(1)), int(m.group(2)), int(m.group(3))
        m = re.match(r"([0-9.]+)% CPU use", line)
        if m:
            d["cpu"] = float(m.group(1)) / 100.0
        m = re.match(r"(Pair|Modify|Comm) +\| +[0-9.eE+-]+ +\| +([0-9.eE+-]+)", line)
        if m:
            d[m.group(1)] = float(m.group(2))    # average over the ranks
        m = re.match(r"Nghost:\s+([0-9.eE+-]+) ave", line)
        if m:
            d["ghosts"] = float(m.group(1))
        m = re.match(r"Neighbor list builds = (\d+)", line)
        if m:
            d["builds"] = int(m.group(1))
        m = re.match(r"EFFECTS nodes (\d+) contacts (\S+) needle_visits (\S+)", line)
        if m:
            d["contacts"], d["visits"] = float(m.group(2)), float(m.group(3))
    return d

# CPU time (loop time x LAMMPS's "CPU use") rather than wall time: on a shared machine a run
# waits for a core for a varying share of its wall time; the sections are scaled by the same share
per = lambda d, key="loop": 1e6 * d[key] * d["cpu"] / (d["nodes"] * d["steps"])
wall = lambda d: 1e6 * d["loop"] / (d["nodes"] * d["steps"])
for frozen in modes:
    what = "same configuration every step" if frozen == "1" else "moving as in the stage"
    print(f"\n{np} rank(s), {steps} steps, {what}; CPU time per node-step in us (least of {reps}); "
          "ratio = CPU time per node-step / the baseline's")
    print("| effect | nodes | step | pair | fixes | comm | ratio | ratio per repetition | wall-time ratio | list builds | ghosts/rank | contacts | needle visits/step |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    base = {}
    for k, (name, rs, _) in enumerate(variants):
        runs = [read(f"v{k}.f{frozen}.r{r}.log") for r in range(1, reps + 1)]
        if rs not in base:
            base[rs] = (k, runs)
        bk, bruns = base[rs]
        best, bbest = min(runs, key=per), min(bruns, key=per)
        each = ", ".join(f"{per(a) / per(b):.2f}" for a, b in zip(runs, bruns))
        wr = min(wall(a) for a in runs) / min(wall(b) for b in bruns)
        print(f"| {name} | {best['nodes']} | {per(best):.4f} | {per(best, 'Pair'):.4f} | {per(best, 'Modify'):.4f} | "
              f"{per(best, 'Comm'):.4f} | {'1' if k == bk else f'{per(best) / per(bbest):.3f}'} | {each} | "
              f"{'1' if k == bk else f'{wr:.2f}'} | {best['builds']} | {best.get('ghosts', 0):.0f} | "
              f"{best.get('contacts', 0):.0f} | {best.get('visits', 0.0):.0f} |")
PY
