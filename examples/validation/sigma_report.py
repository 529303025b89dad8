#!/usr/bin/env python3
"""Table of the sigma study (sigma.sh): per sigma, the 0 deg layer's channel width, open channels
and cracks and the 90 deg layer's cracks (how many of the stitching points have one, and their length), from each run's ncf-measure-summary.csv, with the orientation SD of both
layers and the wall time; the deviation maps of each run listed below the table.
Usage: sigma_report.py OUT sigma [sigma ...]   (markdown on stdout)"""
import csv
import os
import sys


def summary(path):
    rows = {}
    with open(path) as f:
        for r in csv.DictReader(f):
            rows[(int(r["layer"]), r["metric"])] = r
    return rows


def cell(rows, layer, metric, digits=2):
    r = rows.get((layer, metric))
    if r is None or r["n"] in ("", "0"):
        return "–"
    if r["sd"] == "":
        return f"{float(r['mean']):.{digits}f} ({r['n']})"
    return f"{float(r['mean']):.{digits}f} ± {float(r['sd']):.{digits}f} ({r['n']})"


def count(rows, layer, metric, of):
    """'k of n': how many measurements of metric there are out of those of the metric 'of'"""
    r, t = rows.get((layer, metric)), rows.get((layer, of))
    k = int(r["n"]) if r is not None and r["n"] else 0
    n = int(t["n"]) if t is not None and t["n"] else 0
    return f"{k} of {n}"


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    out, sigmas = sys.argv[1], sys.argv[2:]
    print("| σ of both layers | 0° layer: orientation SD [°] | 0° layer: channel width [mm] (n) "
          "| 0° layer: open channels | 0° layer: cracks | 0° layer: crack length [mm] (n) "
          "| 90° layer: orientation SD [°] | 90° layer: cracks | 90° layer: crack length [mm] (n) "
          "| wall time |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    maps = []
    for s in sigmas:
        name = f"ncf090_s{s}"
        d = os.path.join(out, f"measure-{name}")
        path = os.path.join(d, "ncf-measure-summary.csv")
        if not os.path.exists(path):
            sys.exit(f"sigma_report.py: no {path}: run sigma.sh first")
        rows = summary(path)
        wall = "–"
        wpath = os.path.join(out, f"{name}.wall")
        if os.path.exists(wpath):
            w = open(wpath).read().split()
            wall = f"{int(w[2]) // 60} min {int(w[2]) % 60} s ({w[4]} ranks)"
        print(f"| {s}° | {cell(rows, 1, 'orientation deviation SD')} "
              f"| {cell(rows, 1, 'channel width (middle between stitching points)')} "
              f"| {count(rows, 1, 'channel width where open', 'channel width (middle between stitching points)')} "
              f"| {count(rows, 1, 'crack length', 'stitching points without a visible crack')} "
              f"| {cell(rows, 1, 'crack length')} | {cell(rows, 2, 'orientation deviation SD')} "
              f"| {count(rows, 2, 'crack length', 'stitching points without a visible crack')} "
              f"| {cell(rows, 2, 'crack length')} | {wall} |")
        maps += [os.path.join(f"measure-{name}", f) for f in sorted(os.listdir(d)) if f.endswith("-map.png")]
    print()
    for m in maps:
        print(f"![{os.path.basename(m)}]({m})")


if __name__ == "__main__":
    main()
