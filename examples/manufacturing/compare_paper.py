#!/usr/bin/env python3
"""The measured defects of the as-manufactured fabrics beside the paper's Tables 2 and 4.

Usage: compare_paper.py [--ncf090 CSV] [--ncf45 CSV]
CSV: the ncf-measure summary (ncf-measure-summary.csv) of the fabric's release data file. Prints a
Markdown table: experiment (Table 2) | paper's simulation (Table 4) | ours (mean ± SD, n).
"""
import argparse
import csv
import math
import sys

# (fabric, nominal angle of the layer, metric as ncf-measure names it, label,
#  experiment mean, SD, paper's simulation mean, SD, unit)
PAPER = [
    ("ncf090", 0.0, "channel width (middle between stitching points)", "0° layer: channel width",
     0.50, 0.24, 0.31, 0.10, "mm"),
    ("ncf090", 90.0, "crack length", "90° layer: crack length", 2.30, 0.70, 1.97, 0.47, "mm"),
    ("ncf45", 45.0, "crack length", "+45° layer: crack length", 3.19, 0.81, 2.08, 0.83, "mm"),
    ("ncf45", 45.0, "crack width", "+45° layer: crack width", 0.21, 0.09, 0.12, 0.05, "mm"),
    ("ncf45", 45.0, "stitching points without a visible crack",
     "+45° layer: stitching points without a visible crack", 35, None, 31, None, "%"),
    ("ncf45", -45.0, "crack length", "−45° layer: crack length", 3.58, 0.89, 2.62, 1.13, "mm"),
    ("ncf45", -45.0, "crack width", "−45° layer: crack width", 0.22, 0.09, 0.17, 0.05, "mm"),
    ("ncf45", None, "loop tilt from x (magnitude)", "−45° face: loop tilt from the machine direction",
     14.9, 1.3, 6.7, 3.1, "°"),
]


def read(path):
    rows = {}
    with open(path) as f:
        for r in csv.DictReader(f):
            ang = None if r["nominal_deg"] in ("", "nan") else float(r["nominal_deg"])
            rows[(ang, r["metric"])] = r
    return rows


def pm(m, s):
    return f"{m:g}" if s is None else f"{m:g} ± {s:g}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--ncf090")
    ap.add_argument("--ncf45")
    a = ap.parse_args()
    data = {k: read(v) for k, v in (("ncf090", a.ncf090), ("ncf45", a.ncf45)) if v}
    print("| fabric | metric | experiment (Table 2) | paper's simulation (Table 4) | ours: mean ± SD (n) |")
    print("|---|---|---|---|---|")
    for fab, ang, metric, label, em, es, sm, ss, unit in PAPER:
        if fab not in data:
            continue
        r = data[fab].get((ang, metric))
        if r is None or not r["n"] or int(float(r["n"])) == 0:
            ours = "not measured (none found)"
        else:
            m = float(r["mean"])
            s = r["sd"]
            s = None if s in ("", "nan") or math.isnan(float(s)) else float(s)
            ours = f"{pm(round(m, 3), None if s is None else round(s, 3))} ({int(float(r['n']))})"
        print(f"| {'0°/90°' if fab == 'ncf090' else '±45°'} | {label} | {pm(em, es)} {unit} | "
              f"{pm(sm, ss)} {unit} | {ours} {unit if 'not' not in ours else ''} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
