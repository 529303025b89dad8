#!/bin/bash
# How cost grows (issue 16, item 5): the wall time per step of each manufacturing stage against
# the RVE size, for the +-45 card (examples/gen-ncf45/ncf45.card) on 1 and 2 MPI ranks, with the
# ghost atoms and the communication share of each stage, for the estimate in bench/README.md
# ("How cost grows").
#
# Running the five stages through for a 4x4 RVE takes hours; the steps of a stage cost what its
# state and its effects cost, not how it got there. So the elementary RVE goes through stages 1-3
# once (untimed, as in bench/effects.sh), and each stage's state is copied R x R in the plane
# (replicate_data.py: the copies joined by their bonds across the periodic faces, the chain ends
# at the inner seams free) and timed over a fixed number of steps (bench/in.effects) with the
# stage's effects:
#   compact     the compacted state, plates at the layer thickness, chain ends moving only in z
#   pierce      the pierced state, needles through the mat
#   stitch      the stitched state (with the yarn), needles gone
#   pretension  the same with the yarn's rest length shrinking (fix ncf/shrink, in the ramp)
#   release     the same without plates
# (stages 4 and 5 start from the stitched state, not from their own: an approximation of their
# contacts). All with friction and averaged PBC on the outer faces. By default every step
# evaluates the same configuration (no time integration, NCF_BENCH_FROZEN=1): the free chain ends
# at the inner seams of a copied state spring back when it moves, and their motion (list builds,
# new contacts) would be charged to the larger RVEs; NCF_BENCH_FROZEN=0 moves it.
#
# Usage: bench/scaling.sh [R ...]   (default: 1 2 3 4; R x R copies of the elementary RVE)
# NCF_BENCH_NP="1 2" rank counts; NCF_BENCH_STEPS (default 200) timed steps per stage;
# NCF_BENCH_FROZEN (default 1, above);
# NCF_BENCH_SCENE=DIR the stage outputs of an earlier run (see bench/effects.sh); NCF_BENCH_KEEP=1
# keeps the outputs (folder printed). After tools/setup.sh (uses build/ncf-env.sh).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
source "$here/common.sh"
sizes=("$@")
[ ${#sizes[@]} -gt 0 ] || sizes=(1 2 3 4)
nps=${NCF_BENCH_NP:-1 2}
steps=${NCF_BENCH_STEPS:-200}
bench_work scaling
bench_scene ncf45
prefix=ncf45
for f in "$scene/$prefix".*; do ln -sf "$f" "$work/"; done
cd "$work"
pretension=$(awk '$2 == "ncf_pretension" {print $4}' "$prefix.settings.lmp")
lmprun() { if [ "$1" -gt 1 ]; then mpirun -np "$1" --oversubscribe lmp "${@:2}"; else lmp "${@:2}"; fi; }
stages=(compact pierce stitch pretension release)
declare -A state=([compact]=compact [pierce]=pierce [stitch]=stitch [pretension]=stitch [release]=stitch)
declare -A args=([compact]="-var endsz 1" [pierce]="-var needles in" [stitch]=""
  [pretension]="-var shrink $pretension -var ramp 10000" [release]="-var shrink $pretension -var ramp 10000 -var plates none")
for r in "${sizes[@]}"; do
  for st in compact pierce stitch; do
    /usr/bin/python3 -B "$here/replicate_data.py" "$prefix.$st.data" "r$r.$st.data" "$r" --needles "$prefix.needles" "r$r.needles"
  done
  for st in "${stages[@]}"; do
    for np in $nps; do
      # shellcheck disable=SC2086  (the variables are words)
      lmprun "$np" -in "$here/in.effects" -var prefix "$prefix" -var here "$man" -var fromdata 1 \
        -var data "r$r.${state[$st]}.data" -var needle_file "r$r.needles" -var frozen "${NCF_BENCH_FROZEN:-1}" \
        -var steps "$steps" ${args[$st]} -log "r$r.$st.np$np.log" -screen none
    done
  done
  echo "RVE ${r}x${r} done"
done

/usr/bin/env python3 - "$work" "$nps" "${sizes[@]}" <<'PY'
import re, sys, os
work, nps, sizes = sys.argv[1], [int(p) for p in sys.argv[2].split()], [int(s) for s in sys.argv[3:]]
stages = ["compact", "pierce", "stitch", "pretension", "release"]

def stage(path):
    """the timed run (the last of the log; the first is a short warm-up): loop time, steps, nodes,
    CPU share, comm time (rank average), ghost atoms per rank (average), list builds"""
    d = {"t": 0.0, "s": 1, "n": 1, "cpu": 1.0, "comm": 0.0, "g": 0.0, "b": 0}
    for line in open(path):
        m = re.match(r"Loop time of ([0-9.eE+-]+) on \d+ procs for (\d+) steps with (\d+) atoms", line)
        if m:
            d["t"], d["s"], d["n"] = float(m.group(1)), int(m.group(2)), int(m.group(3))
        m = re.match(r"([0-9.]+)% CPU use", line)
        if m:
            d["cpu"] = float(m.group(1)) / 100.0
        m = re.match(r"Comm +\| +[0-9.eE+-]+ +\| +([0-9.eE+-]+)", line)
        if m:
            d["comm"] = float(m.group(1))
        m = re.match(r"Nghost:\s+([0-9.eE+-]+) ave", line)
        if m:
            d["g"] = float(m.group(1))
        m = re.match(r"Neighbor list builds = (\d+)", line)
        if m:
            d["b"] = int(m.group(1))
    return d

rows = {(r, p, st): stage(os.path.join(work, f"r{r}.{st}.np{p}.log")) for r in sizes for p in nps for st in stages}
# CPU time = loop time x LAMMPS's "CPU use" (on a shared machine the wall time also counts the
# waits for a core; on several ranks MPI's busy wait counts as CPU use, so there the wall time
# is the measure)
cpu = lambda d: d["t"] * d["cpu"]
print("| RVE | stage | nodes | " + " | ".join(
    f"{p} rank(s): CPU us/node-step, wall ms/step, comm %, ghosts/rank, list builds" for p in nps) + " |")
print("|---|---|---|" + "---|" * len(nps))
for st in stages:
    for r in sizes:
        cells = []
        for p in nps:
            d = rows[r, p, st]
            cells.append(f"{1e6 * cpu(d) / (d['s'] * d['n']):.3f}, {1e3 * d['t'] / d['s']:.1f}, "
                         f"{100 * d['comm'] / d['t']:.0f}, {d['g']:.0f}, {d['b']}")
        print(f"| {r}x{r} | {st} | {rows[r, nps[0], st]['n']} | " + " | ".join(cells) + " |")
if 1 in nps and len(sizes) > 1:
    print()
    # linear growth on 1 rank: cost per node-step of each size against the elementary RVE's, and a
    # least-squares fit of the CPU time per step to c N + g G (N nodes, G ghost atoms)
    for st in stages:
        ds = [rows[r, 1, st] for r in sizes]
        per = [cpu(d) / (d["s"] * d["n"]) for d in ds]
        y = [cpu(d) / d["s"] for d in ds]
        a11 = sum(d["n"] ** 2 for d in ds); a12 = sum(d["n"] * d["g"] for d in ds); a22 = sum(d["g"] ** 2 for d in ds)
        b1 = sum(d["n"] * t for d, t in zip(ds, y)); b2 = sum(d["g"] * t for d, t in zip(ds, y))
        det = a11 * a22 - a12 * a12
        c = (b1 * a22 - b2 * a12) / det; g = (a11 * b2 - a12 * b1) / det
        print(f"{st}: CPU time per node-step relative to {sizes[0]}x{sizes[0]}: " +
              ", ".join(f"{r}x{r} {p / per[0]:.2f}" for r, p in zip(sizes, per)) +
              f"; fit per step = c N + g G: c {1e6 * c:.3f} us per node, g {1e6 * g:.3f} us per ghost")
PY
