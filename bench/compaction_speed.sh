#!/bin/bash
# What a quasi-static compaction costs (stage 1, examples/manufacturing/in.compact). The plate
# speed follows from the accepted dynamic pressure pdyn = rho_mat v^2; slower is closer to
# quasi-static and costs steps in proportion to 1/sqrt(pdyn). For each pdyn the script compacts
# the same small generated fabric (examples/needles/mini.card: 0/90 deg, sigma 3 deg, 771 nodes)
# to t_L and prints, relative to the fastest run: steps, wall time, compaction pressure at t_L,
# largest chain-chain penetration and kinetic energy against the plate work at the end.
# Usage: bench/compaction_speed.sh [PDYN ...]   (default 1e4 3e3 1e3 3e2; after tools/setup.sh)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
source "${NCF_BUILD:-$root/build}/ncf-env.sh"
levels=("$@")
[ ${#levels[@]} -gt 0 ] || levels=(1e4 3e3 1e3 3e2)
work=$(mktemp -d /tmp/ncf-bench-compaction.XXXXXX)
[ -n "${NCF_BENCH_KEEP:-}" ] || trap 'rm -rf "$work"' EXIT
cd "$work"
echo "load average before the runs: $(cut -d' ' -f1-3 /proc/loadavg) on $(nproc) cores"
ncf-gen "$root/examples/needles/mini.card" -o mini -q
for p in "${levels[@]}"; do
  mkdir -p "run_$p"
  lmp -in "$root/examples/manufacturing/in.compact" -var prefix mini -var pdyn "$p" \
    -var here "$root/examples/manufacturing" \
    -var out "run_$p" -var hold 1000 -log "mini.$p.log" -screen none
done
python3 - "${levels[@]}" <<'PY'
import re, sys
rows = []
for p in sys.argv[1:]:
    log = open(f"mini.{p}.log").read()
    c = dict(zip(*[iter(re.search(r"^COMPACTION (.*)$", log, re.M).group(1).split())] * 2))
    wall = sum(float(t) for t in re.findall(r"^Loop time of ([0-9.eE+-]+)", log, re.M))
    rows.append((p, int(c["steps"]), wall, float(c["pressure"]), float(c["maxpen_chain"]) / float(c["d"]),
                 float(c["ke_over_work"]), float(c["speed"])))
s0, w0, p0 = rows[0][1], rows[0][2], rows[0][3]
print(f"{'pdyn [Pa]':>10} {'v [m/s]':>8} {'steps':>7} {'steps/ref':>9} {'wall/ref':>8} "
      f"{'p(t_L) [Pa]':>12} {'p/ref':>6} {'max pen/d':>9} {'KE/work':>9}")
for p, s, w, pr, pen, ke, v in rows:
    print(f"{p:>10} {v:8.3f} {s:7d} {s / s0:9.2f} {w / w0:8.2f} {pr:12.4g} {pr / p0:6.3f} {pen:9.3f} {ke:9.2e}")
print(f"slowest vs fastest: {rows[-1][1] / s0:.2f}x the steps, pressure at t_L changes by "
      f"{100 * (rows[-1][3] / p0 - 1):+.1f} %")
PY
