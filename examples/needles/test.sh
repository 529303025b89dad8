#!/usr/bin/env bash
# ctest (label examples): the needle goes through the mat, touches chains on its way, and at the
# end, with its shaft through the whole mat, no chain node is left inside the needle and no chain
# segment crosses it (the chains were pushed out of its way, not pierced), while the mat as a
# whole stayed where it was.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
out=${1:-$(mktemp -d)}
rm -rf "$out" && mkdir -p "$out"
bash "$here/run.sh" "$out"
line=$(grep '^PIERCE' "$out/pierce.log")
/usr/bin/python3 - "$line" "$out/pierce.log" <<'PY'
import sys
w = sys.argv[1].split()[1:]
v = {w[i]: float(w[i + 1]) for i in range(0, len(w), 2)}
# thermo lines: step tip fz contacts penetration ...
rows = []
for l in open(sys.argv[2]):
    p = l.split()
    if len(p) == 8 and p[0].isdigit():
        try:
            rows.append([float(x) for x in p])
        except ValueError:
            pass
cmax = max(r[3] for r in rows)
penmax = max(r[4] for r in rows)
ok = True
if v["tip"] > 0:
    print("the needle did not pass through the mat"); ok = False
if cmax < 1:
    print("the needle never touched a chain"); ok = False
if v["rmin"] < v["radius"]:
    print(f"a chain node is inside the needle: {v['rmin']} < {v['radius']}"); ok = False
if v["npen"] > v["dhalf"]:
    print(f"a chain segment crosses the needle: penetration {v['npen']}"); ok = False
if v["maxpen"] > v["dhalf"]:
    print(f"chain-chain penetration {v['maxpen']} above half a diameter"); ok = False
if v["drift"] > 0.2 * v["radius"]:
    print(f"the mat slid away from the needle by {v['drift']}"); ok = False
print("needle example:", "OK" if ok else "FAIL", v, f"most contacts {cmax:g}, largest needle penetration {penmax:g}")
sys.exit(0 if ok else 1)
PY
ls "$out"/mini.pierce.*.png > /dev/null
