#!/usr/bin/env bash
# The capstan sweep of in.capstan: load ratio (fraction of the Euler-Eytelwein limit exp(mu pi))
# against viscous damping (tau, velocity relaxation time in steps), the rope's creep speed over the
# last quarter of each run; writes OUT/capstan.csv and OUT/capstan.png (doc/pair_ncf_contact.md).
# Usage: bash examples/contact/capstan.sh [OUT]    (default ./capstan-out; about 20 short runs)
#   NCF_CAPSTAN_STEPS (100000), NCF_CAPSTAN_RATIOS, NCF_CAPSTAN_TAUS to change the sweep
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
out=$(mkdir -p "${1:-capstan-out}" && cd "${1:-capstan-out}" && pwd)
source "${NCF_BUILD:-$here/../../build}/ncf-env.sh"
steps=${NCF_CAPSTAN_STEPS:-100000}
ratios=${NCF_CAPSTAN_RATIOS:-0.5 0.7 0.8 0.9 0.95 1.05 1.2}
taus=${NCF_CAPSTAN_TAUS:-200 2000 20000}
cd "$here"
echo "ratio,tau,T1,T2,xtop,creep_speed,ke" > "$out/capstan.csv"
for tau in $taus; do
  for r in $ratios; do
    lmp -in in.capstan -var ratio "$r" -var tau "$tau" -var steps "$steps" -log "$out/capstan.$r.$tau.log" -screen none
    awk '$1 == "CAPSTAN" { print $3 "," $5 "," $9 "," $11 "," $13 "," $15 "," $17 }' "$out/capstan.$r.$tau.log" >> "$out/capstan.csv"
  done
done
/usr/bin/python3 - "$out" <<'PY'
import csv, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
out = sys.argv[1]
rows = list(csv.DictReader(open(f"{out}/capstan.csv")))
fig, ax = plt.subplots(figsize=(6.5, 4.2))
for tau in sorted({int(r["tau"]) for r in rows}):
    rs = sorted((float(r["ratio"]), abs(float(r["creep_speed"]))) for r in rows if int(r["tau"]) == tau)
    ax.semilogy([a for a, _ in rs], [max(v, 1e-12) for _, v in rs], "o-", label=f"tau = {tau} steps")
ax.axvline(1.0, color="k", lw=0.8, ls="--")
ax.set_xlabel("T2 / (T1 exp(mu pi)): load as a fraction of the capstan limit")
ax.set_ylabel("rope speed over the last quarter [m/s]")
ax.set_title("rope over a drum, half a turn, mu = 0.3 (examples/contact/in.capstan)", fontsize=9)
ax.legend()
fig.tight_layout()
fig.savefig(f"{out}/capstan.png", dpi=110)
print("| ratio | " + " | ".join(f"tau {t}" for t in sorted({int(r['tau']) for r in rows})) + " |")
print("|---|" + "---|" * len({r['tau'] for r in rows}))
for ratio in sorted({float(r["ratio"]) for r in rows}):
    cells = [f"{float(r['creep_speed']):.2g}" for t in sorted({int(r['tau']) for r in rows})
             for r in rows if float(r["ratio"]) == ratio and int(r["tau"]) == t]
    print(f"| {ratio:g} | " + " | ".join(cells) + " |")
PY
