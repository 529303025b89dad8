#!/bin/bash
# Cost of each manufacturing stage (examples/manufacturing, stages 1-5) for the paper's two
# elementary RVEs on 1 and 2 MPI ranks: wall time (LAMMPS loop time) per stage, steps, and the cost
# per node-step, plus the 1 -> 2 rank speed-up per stage. One run of each, on this machine.
# Usage: bench/stages.sh [FABRIC ...]   (default: ncf45 ncf090; after tools/setup.sh)
# NCF_BENCH_NP="1 2" (rank counts), NCF_BENCH_KEEP=1 keeps the outputs (folder printed)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
source "${NCF_BUILD:-$root/build}/ncf-env.sh"
fabrics=("$@")
[ ${#fabrics[@]} -gt 0 ] || fabrics=(ncf45 ncf090)
work=$(mktemp -d /tmp/ncf-stages.XXXXXX)
[ -n "${NCF_BENCH_KEEP:-}" ] && echo "outputs in $work" || trap 'rm -rf "$work"' EXIT
echo "load average before the runs: $(cut -d' ' -f1-3 /proc/loadavg) on $(nproc) cores (timings are only comparable on an idle machine)"
for np in ${NCF_BENCH_NP:-1 2}; do
  for fab in "${fabrics[@]}"; do
    NCF_NP=$np bash "$root/examples/manufacturing/run.sh" "$work/np$np" "$fab" > "$work/$fab.np$np.out"
  done
done
python3 - "$work" ${NCF_BENCH_NP:-1 2} -- "${fabrics[@]}" <<'PY'
import re, sys, os
work = sys.argv[1]
k = sys.argv.index("--")
nps, fabrics = [int(x) for x in sys.argv[2:k]], sys.argv[k + 1:]
stages = ["compact", "pierce", "stitch", "pretension", "release"]
def loop(path):
    t = s = n = 0
    for line in open(path):
        m = re.match(r"Loop time of ([0-9.eE+-]+) on \d+ procs for (\d+) steps with (\d+) atoms", line)
        if m:
            t += float(m.group(1)); s += int(m.group(2)); n = int(m.group(3))
    return t, s, n
print(f"| fabric | stage | nodes | steps | " + " | ".join(f"{p} rank(s): wall [s], us/node-step" for p in nps) + " | speed-up |")
print("|---|---|---|---|" + "---|" * len(nps) + "---|")
for fab in fabrics:
    tot = {p: 0.0 for p in nps}
    for st in stages:
        cells, times = [], {}
        for p in nps:
            t, s, n = loop(os.path.join(work, f"np{p}", f"{fab}.{st}.log"))
            times[p] = t; tot[p] += t
            cells.append(f"{t:.1f}, {1e6 * t / max(s * n, 1):.3f}")
        sp = times[nps[0]] / times[nps[-1]] if len(nps) > 1 and times[nps[-1]] > 0 else float("nan")
        print(f"| {fab} | {st} | {n} | {s} | " + " | ".join(cells) + f" | {sp:.2f} |")
    sp = tot[nps[0]] / tot[nps[-1]] if len(nps) > 1 else float("nan")
    print(f"| {fab} | all | | | " + " | ".join(f"{tot[p]:.1f}" for p in nps) + f" | {sp:.2f} |")
PY
