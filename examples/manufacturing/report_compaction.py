#!/usr/bin/env python3
"""Report of a compaction stage (in.compact): compaction curve and checks.

Usage: report_compaction.py LOG [LOG ...] --out DIR
Reads the thermo output of each log (columns of in.compact's thermo_style), writes
DIR/compaction_curve.png (compaction pressure against the fibre volume fraction of the layers,
one curve per log) and prints a Markdown table per log: final gap against the target sum(t_L),
pressure, kinetic energy against the work of the plate, largest penetrations, wall time.
Exit status 1 if a check fails (gap off by more than 1 % of sum(t_L), a chain penetrating
another by half its diameter or a plate by its radius, i.e. a possible pass-through).
"""
import argparse
import os
import re
import sys


def thermo_blocks(path):
    """All thermo blocks of a log as lists of dicts."""
    blocks, header = [], None
    for line in open(path):
        w = line.split()
        if w and w[0] == "Step":
            header, rows = w, []
            blocks.append(rows)
            continue
        if header:
            if len(w) != len(header):
                header = None
                continue
            try:
                blocks[-1].append({h: float(v) for h, v in zip(header, w)})
            except ValueError:
                header = None
    return blocks


def printed(path, tag):
    """key value pairs of the last line starting with tag."""
    found = None
    for line in open(path):
        if line.startswith(tag + " "):
            w = line.split()[1:]
            found = {w[i]: float(w[i + 1]) for i in range(0, len(w) - 1, 2)}
    return found or {}


def loop_time(path):
    total = 0.0
    for line in open(path):
        m = re.match(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", line)
        if m:
            total += float(m.group(1))
    return total


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("logs", nargs="+")
    ap.add_argument("--out", default=".")
    args = ap.parse_args()
    ok = True
    curves = []
    lines = []
    for log in args.logs:
        name = os.path.basename(log).split(".")[0]
        rows = [r for b in thermo_blocks(log) for r in b]
        res = printed(log, "COMPACTION")
        if not rows or not res:
            print(f"report_compaction.py: {log} has no thermo output or no COMPACTION line")
            return 1
        curves.append((name, [r["v_vf"] for r in rows], [r["f_plates[5]"] for r in rows]))
        gap, target = res["gap"], res["target"]
        pen_chain, d = res["maxpen_chain"], res["d"]
        pen_plate = res["maxpen_plate"]
        gap_ok = abs(gap - target) <= 0.01 * target
        chain_ok = pen_chain < 0.5 * d
        plate_ok = pen_plate < 0.5 * d
        ok &= gap_ok and chain_ok and plate_ok
        lines += [f"## {name}: compaction to the layer thickness", "",
                  "| quantity | value | check |", "|---|---|---|",
                  f"| final gap / sum of t_L (Eq. 1) | {gap * 1e3:.4f} mm / {target * 1e3:.4f} mm"
                  f" | {'ok' if gap_ok else 'FAIL'} (1 %) |",
                  f"| fibre volume fraction of the layers | {res['vf']:.3f} | V_L = 0.20 at t_L |",
                  f"| compaction pressure at t_L (held) | {res['pressure']:.4g} Pa | |",
                  f"| plate speed, accepted dynamic pressure | {res['speed']:.3g} m/s, {res['pdyn']:.3g} Pa | |",
                  f"| largest chain-chain penetration (whole run) | {pen_chain * 1e6:.2f} um = "
                  f"{pen_chain / d:.3f} d_c | {'ok' if chain_ok else 'FAIL'}: < d_c/2, no pass-through |",
                  f"| largest chain-plate penetration (whole run) | {pen_plate * 1e6:.2f} um = "
                  f"{pen_plate / d:.3f} d_c | {'ok' if plate_ok else 'FAIL'}: < d_c/2 |",
                  f"| kinetic energy / plate work at the end | {res['ke_over_work']:.3g} | quasi-static if << 1 |",
                  f"| averaged PBC violation (end) | {res['pbc']:.3g} m | round-off |",
                  f"| steps, wall time | {int(res['steps'])}, {loop_time(log):.1f} s | |", ""]
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(5.5, 3.8))
        for name, vf, p in curves:
            ax.plot(vf, [max(x, 1e-3) for x in p], label=name)
        ax.set_yscale("log")
        ax.set_xlabel("fibre volume fraction of the layers")
        ax.set_ylabel("compaction pressure [Pa]")
        ax.axvline(0.20, color="gray", ls=":", label="V_L = 0.20 (t_L)")
        ax.legend()
        fig.tight_layout()
        fig.savefig(os.path.join(args.out, "compaction_curve.png"), dpi=120)
        lines.append("Compaction curve: `compaction_curve.png`.")
    except ImportError:
        lines.append("(matplotlib missing: no compaction curve)")
    lines.append("")
    lines.append("Result: " + ("PASS" if ok else "FAIL"))
    text = "\n".join(lines) + "\n"
    with open(os.path.join(args.out, "compaction.md"), "w") as f:
        f.write(text)
    print(text)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
