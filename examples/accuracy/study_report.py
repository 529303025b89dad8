#!/usr/bin/env python3
"""The accuracy study's report: every run of study.sh against the reference variant.

Usage: study_report.py OUT [--ref fine] [--variants variants.txt]
Reads OUT/VARIANT-seedN/ (run.info: wall time and peak memory; the stage logs; ncf-measure's
summary) and writes OUT/accuracy.csv (one line per run) and OUT/accuracy.md: per variant the
metrics (mean ± SD over the seeds), the cost (nodes, steps, wall time, peak memory), and the error
of each metric: |variant mean − reference mean| beside the seed scatter of the two (the
root-sum-square of their SDs, so that an error below it is not resolved by the seeds), the cost as
node-steps (nodes × steps, which the load of the machine does not change) and wall time relative to
the reference, and a plot of the error against the wall time, OUT/accuracy.png.
"""
import argparse
import csv
import glob
import math
import os
import sys

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "..", "manufacturing"))
from report_manufacturing import loop_time, printed, summary_value  # noqa: E402

STAGES = ("compact", "pierce", "stitch", "pretension", "release")
# (key, label, unit): the metrics compared
METRICS = [
    ("sd1", "orientation SD, layer 1", "°"),
    ("sd2", "orientation SD, layer 2", "°"),
    ("crack1", "crack length, layer 1", "mm"),
    ("crack2", "crack length, layer 2", "mm"),
    ("width1", "crack width, layer 1", "mm"),
    ("width2", "crack width, layer 2", "mm"),
    ("channel1", "channel width, layer 1", "mm"),
    ("tilt", "loop tilt", "°"),
    ("thick", "thickness after release / Σt_L", ""),
    ("pen", "largest penetration / d_c", ""),
]
COST = [("nodes", "nodes"), ("steps", "steps"), ("wall", "wall time [s]"), ("mem", "peak memory [MB]")]


def measured(path):
    """ncf-measure's summary: {(layer, metric): mean}"""
    out = {}
    with open(path) as f:
        for r in csv.DictReader(f):
            try:
                out[(int(r["layer"]), r["metric"])] = float(r["mean"])
            except ValueError:
                pass
    return out


def one_run(d):
    info = open(os.path.join(d, "run.info")).read().split()
    variant, seed, ranks, wall, mem_kb, prefix = info[0], int(info[1]), int(info[2]), \
        float(info[3]), float(info[4]), info[5]
    r = {"variant": variant, "seed": seed, "ranks": ranks, "wall": wall, "mem": mem_kb / 1024.0}
    steps, pen = 0, 0.0
    for st in STAGES:
        log = os.path.join(d, f"{prefix}.{st}.log")
        steps += loop_time(log)[1]
        tag = {"compact": "COMPACTION", "pierce": "PIERCE", "stitch": "STITCH",
               "pretension": "PRETENSION", "release": "RELEASE"}[st]
        line = printed(log, tag) or {}
        if "maxpen_chain" in line:
            dc = float(line.get("d", 0.0) or 2.0 * float(line.get("dhalf", 0.0)))
            pen = max(pen, float(line["maxpen_chain"]) / dc)
    r["steps"] = steps
    r["pen"] = pen
    rel = printed(os.path.join(d, f"{prefix}.release.log"), "RELEASE")
    r["thick"] = float(rel["thickness"]) / float(rel["tL_sum"])
    summ = os.path.join(d, f"{prefix}.summary")
    # "total atoms, bonds   N, M"
    r["nodes"] = int(summary_value(summ, "total atoms, bonds")[0].rstrip(","))
    m = measured(os.path.join(d, "measure", "ncf-measure-summary.csv"))
    get = lambda layer, name: m.get((layer, name), float("nan"))  # noqa: E731
    r["sd1"] = get(1, "orientation deviation SD")
    r["sd2"] = get(2, "orientation deviation SD")
    r["crack1"] = get(1, "crack length")
    r["crack2"] = get(2, "crack length")
    r["width1"] = get(1, "crack width")
    r["width2"] = get(2, "crack width")
    r["channel1"] = get(1, "channel width (middle between stitching points)")
    r["tilt"] = get(0, "loop tilt from x (magnitude)")
    return r


def stats(values):
    v = [x for x in values if not math.isnan(x)]
    if not v:
        return float("nan"), float("nan"), 0
    mean = sum(v) / len(v)
    sd = math.sqrt(sum((x - mean) ** 2 for x in v) / (len(v) - 1)) if len(v) > 1 else float("nan")
    return mean, sd, len(v)


def fmt(x, digits=3):
    if isinstance(x, float) and math.isnan(x):
        return "–"
    if isinstance(x, int):
        return f"{x:,}".replace(",", " ")
    return f"{x:.{digits}g}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out")
    ap.add_argument("--ref", default="fine")
    ap.add_argument("--variants", default=os.path.join(here, "variants.txt"))
    a = ap.parse_args()
    desc, order = {}, []
    for line in open(a.variants):
        if line.strip() and not line.startswith("#"):
            f = [x.strip() for x in line.split("|")]
            desc[f[0]] = f[4]
            order.append(f[0])
    runs = []
    for d in sorted(glob.glob(os.path.join(a.out, "*-seed*"))):
        if os.path.exists(os.path.join(d, "run.info")) and \
                os.path.exists(os.path.join(d, "measure", "ncf-measure-summary.csv")):
            runs.append(one_run(d))
    if not runs:
        sys.exit(f"study_report.py: no finished run in {a.out}")
    keys = ["variant", "seed", "ranks"] + [k for k, _ in COST] + [k for k, _, _ in METRICS]
    with open(os.path.join(a.out, "accuracy.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
        w.writeheader()
        for r in runs:
            w.writerow(r)
    by = {}
    for r in runs:
        by.setdefault(r["variant"], []).append(r)
    variants = [v for v in order if v in by] + sorted(v for v in by if v not in order)
    st = {v: {k: stats([r[k] for r in by[v]]) for k in [c for c, _ in COST] + [m for m, _, _ in METRICS]}
          for v in variants}
    ref = st.get(a.ref)
    lines = [f"# Accuracy study ({len(runs)} runs)", ""]
    lines.append("Cost per variant (mean over its seeds; wall time on "
                 f"{runs[0]['ranks']} rank(s)):")
    lines.append("")
    lines.append("| variant | what it varies | seeds | " + " | ".join(l for _, l in COST) + " |")
    lines.append("|---|---|---|" + "---|" * len(COST))
    for v in variants:
        lines.append(f"| {v} | {desc.get(v, '')} | {st[v]['wall'][2]} | " +
                     " | ".join(fmt(int(round(st[v][k][0])) if k in ("nodes", "steps", "mem")
                                    else st[v][k][0]) for k, _ in COST) + " |")
    lines.append("")
    lines.append("Metrics (mean ± SD over the seeds):")
    lines.append("")
    lines.append("| variant | " + " | ".join(f"{l} {u}".strip() for _, l, u in METRICS) + " |")
    lines.append("|---|" + "---|" * len(METRICS))
    for v in variants:
        cells = []
        for k, _, _ in METRICS:
            m, s, n = st[v][k]
            cells.append(fmt(m) + ("" if math.isnan(s) else f" ± {fmt(s, 2)}"))
        lines.append(f"| {v} | " + " | ".join(cells) + " |")
    if ref:
        lines.append("")
        lines.append(f"Error against the reference `{a.ref}`: |mean − reference mean|, and in "
                     "brackets the seed scatter √(SD² + SD_ref²) (– with one seed); an error below "
                     "its scatter is not resolved:")
        lines.append("")
        lines.append("| variant | node-steps / reference's | wall time / reference's | " +
                     " | ".join(f"{l} {u}".strip() for _, l, u in METRICS) + " |")
        lines.append("|---|---|---|" + "---|" * len(METRICS))
        for v in variants:
            cells = []
            for k, _, _ in METRICS:
                m, s, _ = st[v][k]
                mr, sr, _ = ref[k]
                err = abs(m - mr)
                scat = math.sqrt(s * s + sr * sr) if not (math.isnan(s) or math.isnan(sr)) \
                    else float("nan")
                cells.append(fmt(err, 2) + ("" if math.isnan(scat) else f" ({fmt(scat, 2)})"))
            work = st[v]["nodes"][0] * st[v]["steps"][0] / (ref["nodes"][0] * ref["steps"][0])
            lines.append(f"| {v} | {fmt(work, 2)} | {fmt(st[v]['wall'][0] / ref['wall'][0], 2)} | " +
                         " | ".join(cells) + " |")
        plot(a.out, variants, st, ref, a.ref)
        lines.append("")
        lines.append("![error against wall time](accuracy.png)")
    open(os.path.join(a.out, "accuracy.md"), "w").write("\n".join(lines) + "\n")
    print("\n".join(lines))


def plot(out, variants, st, ref, refname):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    shown = [("crack1", "crack length, layer 1 [mm]"), ("crack2", "crack length, layer 2 [mm]"),
             ("sd2", "orientation SD, layer 2 [°]"), ("thick", "thickness / Σt_L")]
    fig, axes = plt.subplots(1, len(shown), figsize=(4.2 * len(shown), 3.6))
    for ax, (k, label) in zip(axes, shown):
        for v in variants:
            if v == refname:
                continue
            x = st[v]["wall"][0]
            y = abs(st[v][k][0] - ref[k][0])
            if math.isnan(y):
                continue
            ax.plot([x], [y], "o", color="crimson" if v == "base" else "steelblue")
            ax.annotate(v, (x, y), fontsize=7, xytext=(3, 2), textcoords="offset points")
        ax.set_xscale("log")
        ax.set_xlabel("wall time [s]")
        ax.set_ylabel(f"|error| of {label}")
        ax.grid(alpha=0.3)
    fig.suptitle(f"error against the reference '{refname}' and the cost of each run")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "accuracy.png"), dpi=110)


if __name__ == "__main__":
    main()
