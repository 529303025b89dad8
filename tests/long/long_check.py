#!/usr/bin/env python3
"""Checks of tests/long/long_run.sh: every hold run's thermo free of NaN/inf with the atom and bond
counts unchanged and its HOLD_END line there; the 2- and 4-rank end states against the 1-rank one
and the run resumed after SIGKILL against the uninterrupted 2-rank run (largest node distance).
Usage: long_check.py OUT STEPS"""
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples",
                                "manufacturing"))
from report_manufacturing import fibre_diameter, unwrapped_positions    # noqa: E402

BOUND_RANKS = 1e-3    # of the fibre chain diameter: round-off grown over the run, far below a defect
BOUND_RESUME = 1e-3


def thermo(path):
    """The thermo header, its rows (values as floats) and the HOLD_END line of a log."""
    rows, head, cur, end = [], None, None, None
    for line in open(path):
        w = line.split()
        if w[:1] == ["Step"]:
            head = cur = w
        elif cur and len(w) == len(cur) and w[0].isdigit():
            rows.append([float(x) for x in w])
        elif w[:1] == ["HOLD_END"]:
            end = w
        elif w[:2] == ["Loop", "time"]:
            cur = None
    return head, rows, end


def main():
    out, steps = sys.argv[1], int(sys.argv[2])
    d = fibre_diameter(f"{out}/small.settings.lmp")
    ok = True
    for name in ("hold.np1", "hold.np2", "hold.np4", "hold.resumed"):
        head, rows, end = thermo(f"{out}/{name}.log")
        bad = [r[0] for r in rows if any(math.isnan(v) or math.isinf(v) for v in r)]
        na = {r[head.index("Atoms")] for r in rows}
        nb = {r[head.index("v_nbond")] for r in rows}
        good = end is not None and not bad and len(na) == 1 and len(nb) == 1
        ok &= good
        first, last = rows[0], rows[-1]
        print(f"{name}: steps {int(first[0])} -> {int(last[0])}, {len(rows)} thermo rows, atoms {sorted(na)}, "
              f"bonds {sorted(nb)}, NaN/inf rows {len(bad)}, end ke {last[head.index('c_ke')]:.3g} J "
              f"fmax {last[head.index('Fmax')]:.3g} N contacts {int(last[head.index('c_pc[1]')])}: "
              f"{'ok' if good else 'FAIL'}")
    ref = unwrapped_positions(f"{out}/hold.np1.data")[0]
    for name, against, bound in (("hold.np2", "hold.np1", BOUND_RANKS), ("hold.np4", "hold.np1", BOUND_RANKS),
                                 ("hold.resumed", "hold.np2", BOUND_RESUME)):
        a, b = unwrapped_positions(f"{out}/{name}.data")[0], unwrapped_positions(f"{out}/{against}.data")[0]
        dist = max(math.dist(a[i], b[i]) for i in b) if a.keys() == b.keys() else float("inf")
        good = dist <= bound * d
        ok &= good
        print(f"{name} against {against}: largest node distance {dist:.3g} m = {dist / d:.3g} d_c "
              f"(bound {bound:g} d_c): {'ok' if good else 'FAIL'}")
    print("long run:", "PASS" if ok else "FAIL")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
