#!/usr/bin/env python3
"""The measured defects of the as-manufactured fabrics beside the paper's Tables 2 and 4.

Usage: compare_paper.py [--ncf090 CSV [CSV ...]] [--ncf45 CSV [CSV ...]]
CSV: the ncf-measure summary (ncf-measure-summary.csv) of the fabric's release data file; several
(e.g. one per seed) are pooled: the mean and SD of all their measurements together. Prints a
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


def pool(rows):
    """(n, mean, SD or None) of the measurements of several summary rows taken together"""
    parts = []
    for r in rows:
        n = int(float(r["n"])) if r["n"] else 0
        if n == 0:
            continue
        sd = r["sd"]
        sd = None if sd in ("", "nan") or math.isnan(float(sd)) else float(sd)
        parts.append((n, float(r["mean"]), sd))
    if not parts:
        return 0, None, None
    n = sum(p[0] for p in parts)
    mean = sum(p[0] * p[1] for p in parts) / n
    if any(p[2] is None for p in parts) or n < 2:
        return n, mean, (parts[0][2] if len(parts) == 1 else None)
    ss = sum((p[0] - 1) * p[2] ** 2 + p[0] * (p[1] - mean) ** 2 for p in parts)
    return n, mean, math.sqrt(ss / (n - 1))


def pm(m, s):
    return f"{m:g}" if s is None else f"{m:g} ± {s:g}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--ncf090", nargs="+")
    ap.add_argument("--ncf45", nargs="+")
    a = ap.parse_args()
    data = {k: [read(p) for p in v] for k, v in (("ncf090", a.ncf090), ("ncf45", a.ncf45)) if v}
    print("| fabric | metric | experiment (Table 2) | paper's simulation (Table 4) | ours: mean ± SD (n) |")
    print("|---|---|---|---|---|")
    for fab, ang, metric, label, em, es, sm, ss, unit in PAPER:
        if fab not in data:
            continue
        n, m, s = pool([d[(ang, metric)] for d in data[fab] if (ang, metric) in d])
        if n == 0:
            ours = "not measured (none found)"
        else:
            ours = f"{pm(round(m, 3), None if s is None else round(s, 3))} ({n})"
        print(f"| {'0°/90°' if fab == 'ncf090' else '±45°'} | {label} | {pm(em, es)} {unit} | "
              f"{pm(sm, ss)} {unit} | {ours} {unit if 'not' not in ours else ''} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
