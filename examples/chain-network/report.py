#!/usr/bin/env python3
"""Report of the chain-network example: box stress against the analytic value of the rod model.

Reads OUT/pretension.log and OUT/stretch.log, writes OUT/report.md and OUT/stress_strain.png.
Exit status 1 when a measured stress is more than 1 % off the analytic one.
Usage: report.py OUT
"""
import math
import re
import sys

OUT = sys.argv[1] if len(sys.argv) > 1 else "out"

A, N, L, LZ = 2.0e-4, 20, 4.0e-3, 1.0e-3
EA_F = 120e9 * math.pi / 4 * 69e-6 ** 2      # fibre chain axial rigidity [N]
EA_Y = 1.81e9 * math.pi / 4 * 88e-6 ** 2     # yarn chain [N]
N_F0, N_Y, SHRINK = 20, 4, 0.16              # 0 deg chains, yarn chains, pretension


def analytic_pxx(strain):
    """pxx of the box: -(sum of the axial forces of the x chains) * Lx / V (virial)."""
    lx = L * (1 + strain)
    force = N_F0 * EA_F * strain + N_Y * EA_Y * (1 + strain - (1 - SHRINK))
    return -force * lx / (lx * L * LZ)


def thermo(path, cols):
    rows, header = [], None
    for line in open(path):
        w = line.split()
        if w and w[0] == "Step":
            header = w
            continue
        if header and len(w) == len(header):
            try:
                rows.append({h: float(v) for h, v in zip(header, w)})
            except ValueError:
                header = None
    return [[r[c] for c in cols] for r in rows]


def printed(path, tag):
    for line in open(path):
        if line.startswith(tag + " "):
            w = line.split()
            return {w[i]: float(w[i + 1]) for i in range(1, len(w) - 1, 2)}
    raise SystemExit(f"report.py: no '{tag}' line in {path}")


def main():
    pre = printed(f"{OUT}/pretension.log", "PRETENSION")
    st = printed(f"{OUT}/stretch.log", "STRETCH")
    checks = [("after 16 % yarn pretension, box held", 0.0, pre["pxx"], analytic_pxx(0.0)),
              ("after 1 % stretch in x", st["strain"], st["pxx"], analytic_pxx(st["strain"]))]
    ok = True
    lines = ["# chain-network example: report", "",
             "Rod model check: the virial stress of the periodic box against the sum of the axial",
             "forces EA (r - L0 (1 - s)) / L0 of the chains along x (20 fibre chains, 4 yarn chains).", "",
             "| state | strain | pxx measured [Pa] | pxx analytic [Pa] | rel. error |",
             "|---|---|---|---|---|"]
    for name, strain, meas, ana in checks:
        err = abs(meas - ana) / abs(ana)
        ok &= err < 0.01
        lines.append(f"| {name} | {strain:.4f} | {meas:.6g} | {ana:.6g} | {err:.2e} |")
    lines += ["", "Pictures: `stretch.*.png` (dump image; blue 0 deg, orange 90 deg, red yarn),",
              "`stress_strain.png`. Restart files: `pretension.restart`, `stretch.restart`;",
              "final geometry with every L0: `final.data`.", ""]
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        data = thermo(f"{OUT}/stretch.log", ["v_strain", "Pxx"])
        xs = [r[0] for r in data]
        fig, ax = plt.subplots(figsize=(5, 3.5))
        ax.plot([100 * x for x in xs], [-r[1] / 1e6 for r in data], "o", ms=4, label="LAMMPS (-pxx)")
        ax.plot([100 * x for x in xs], [-analytic_pxx(x) / 1e6 for x in xs], "-", label="analytic")
        ax.set_xlabel("box strain in x [%]")
        ax.set_ylabel("tensile stress [MPa]")
        ax.legend()
        fig.tight_layout()
        fig.savefig(f"{OUT}/stress_strain.png", dpi=120)
    except ImportError:
        lines.append("(matplotlib missing: no plot)")
    lines.append("Result: " + ("PASS" if ok else "FAIL") + " (1 % tolerance)")
    open(f"{OUT}/report.md", "w").write("\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
