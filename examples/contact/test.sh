#!/bin/bash
# brief run of the pair ncf/contact examples (ctest label examples): short stages, checks that the
# yarns touch, stick and slide, that the mat gets contacts with small penetrations, and that a rope
# over a drum holds below the capstan limit and slides above it (strong damping, in.capstan)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
out=${1:-$(mktemp -d)}
mkdir -p "$out"
cp "$here"/in.crossed "$here"/in.mat "$here"/in.capstan "$here"/crossed.data "$here"/mat.data \
  "$here"/capstan.data "$out"/
cd "$out"
# lmp and the plugin path from the build (ctest sets NCF_BUILD), else from the default build folder
env_file="${NCF_BUILD:-$here/../../build}/ncf-env.sh"
[ -f "$env_file" ] && source "$env_file"
lmp=lmp
"$lmp" -in in.crossed -var steps 8000 -log log.crossed -screen none
"$lmp" -in in.mat -var steps 20000 -var dump 0 -log log.mat -screen none
for r in 0.9 1.1; do
  "$lmp" -in in.capstan -var ratio $r -var tau 200 -var steps 40000 -log log.capstan.$r -screen none
done
python3 - <<'PY'
import sys
def thermo(path):
    rows, on = [], False
    for line in open(path):
        w = line.split()
        if w and w[0] == "Step":
            on = True
            continue
        if on and w and w[0].isdigit():
            rows.append([float(v) for v in w])
        elif on and w and w[0] == "Loop":
            on = False
    return rows
c = thermo("log.crossed")
n = len(c) // 3
press, stick, slide = c[n - 1], c[2 * n - 1], c[-1]
ok = True
def check(cond, msg):
    global ok
    print(("ok   " if cond else "FAIL ") + msg)
    ok = ok and cond
check(press[1] >= 1, f"crossed: yarns in contact ({press[1]:.0f} segment pairs)")
check(abs(press[7] - 0.02) < 0.002, f"crossed: the contact carries the 20 mN press ({press[7]:.4g} N on the upper yarn)")
check(press[3] < 0.2 * 69e-6, f"crossed: penetration {press[3]:.3g} m below 0.2 D")
dx_stick = abs(stick[6] - press[6]); dx_slide = abs(slide[6] - stick[6])
check(dx_stick < 1e-6, f"crossed: sticks at 0.8 mu F_n (moved {dx_stick:.3g} m)")
check(dx_slide > 1e-5, f"crossed: slides at 1.5 mu F_n (moved {dx_slide:.3g} m)")
m = thermo("log.mat")
check(max(r[2] for r in m) > 20, f"mat: up to {max(r[2] for r in m):.0f} contacts")
check(max(r[4] for r in m) < 0.3 * 69e-6, f"mat: max penetration {max(r[4] for r in m):.3g} m below 0.3 D")
for r, holds in ((0.9, True), (1.1, False)):
    w = [l.split() for l in open(f"log.capstan.{r}") if l.startswith("CAPSTAN")][0]
    v = abs(float(w[w.index("creep_speed") + 1]))
    if holds:
        check(v < 1e-6, f"capstan: the rope holds at {r} of the limit exp(mu pi) (speed {v:.2g} m/s)")
    else:
        check(v > 1e-2, f"capstan: the rope slides at {r} of the limit exp(mu pi) (speed {v:.2g} m/s)")
sys.exit(0 if ok else 1)
PY
