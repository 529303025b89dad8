#!/usr/bin/python3
"""Draws doc/images/ncf-measure-definitions.png: how ncf-measure measures a channel, a crack, a
covered stitching point and a loop tilt (doc/ncf_measure.md). The gaps are synthetic coverage maps;
every number drawn is what the tool's own functions measure on them.

    /usr/bin/python3 -B tools/ncf-measure/doc_figures.py doc/images
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ncf_measure as M  # noqa: E402

import matplotlib  # noqa: E402
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Circle, FancyArrowPatch, Polygon  # noqa: E402

MM = 1e-3


def arrow(ax, p, q, col, text=None, off=(0, 0), fs=8):
    ax.add_patch(FancyArrowPatch(p, q, arrowstyle="<->", mutation_scale=8, color=col, lw=1.2))
    if text:
        ax.annotate(text, ((p[0] + q[0]) / 2, (p[1] + q[1]) / 2), xytext=off,
                    textcoords="offset points", color=col, fontsize=fs, ha="center")


def show(ax, g, covered, title):
    x, y = g.centres()
    ax.imshow(np.where(covered, 0.75, 0.0), origin="lower", cmap="gray", vmin=0, vmax=1,
              extent=[g.xlo / MM, (g.xlo + g.lx) / MM, g.ylo / MM, (g.ylo + g.ly) / MM],
              interpolation="nearest")
    ax.set_title(title, fontsize=9)
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")


def panel_channel(ax):
    g = M.Grid(0.0, 0.0, 5.6 * MM, 2.0 * MM, 5e-6)
    x, y = g.centres()
    X, Y = np.meshgrid(x, y)
    yc, w = 1.0 * MM, 0.3 * MM
    gap = np.abs(Y - yc) < w / 2 + 0.06 * MM * np.sin(2 * math.pi * X / g.lx)
    gap &= ~((X < 0.12 * MM) | (X > g.lx - 0.12 * MM))    # filaments crossing the channel
    needles = np.array([[1.4 * MM, yc], [4.2 * MM, yc]])
    r = M.analyse_gaps(g, ~gap, needles, 0.0, 0.15 * MM, (69e-6 / 2) ** 2)
    show(ax, g, ~gap, "(a) 0 deg layer: channel width in the middle\nbetween two stitching points")
    for p in needles:
        ax.plot(p[0] / MM, p[1] / MM, "r+", ms=9)
        ax.add_patch(Circle(p / MM, 0.15, fill=False, ec="r", ls=":", lw=0.8))
    for c in r["channels"]:
        m = np.array([c["x"], c["y"]]) / MM
        ax.plot(m[0], m[1], "bo", ms=3)
        ax.plot([m[0], m[0]], [m[1] - 0.3, m[1] + 0.3], "b:", lw=0.8)
        if c["width"] > 0:
            lo = m[1] + c["offset"] / MM - c["width"] / MM / 2
            arrow(ax, (m[0] + 0.08, lo), (m[0] + 0.08, lo + c["width"] / MM), "b")
            ax.annotate("w = %.3f mm" % (c["width"] / MM), (m[0] + 0.1, m[1] - 0.75), color="b",
                        fontsize=8)
        else:
            ax.annotate("closed: w = 0", (m[0] + 0.05, m[1] - 0.75), color="b", fontsize=8)
    ax.annotate("stitching points P, Q\n(capture radius dotted)", (1.4, 1.0), xytext=(0.1, 1.6),
                color="r", fontsize=7, arrowprops=dict(arrowstyle="->", color="r", lw=0.6))
    ax.annotate("middle M, line across\n(+-search)", (2.8, 1.45), xytext=(2.95, 1.62),
                color="b", fontsize=7)


def panel_crack(ax):
    g = M.Grid(0.0, 0.0, 4.4 * MM, 3.0 * MM, 5e-6)
    x, y = g.centres()
    X, Y = np.meshgrid(x, y)
    ang = 45.0
    c, s = math.cos(math.radians(ang)), math.sin(math.radians(ang))
    P = np.array([1.6 * MM, 1.4 * MM])
    a, b = 0.9 * MM, 0.11 * MM
    dx, dy = X - P[0] - 0.15 * MM * c, Y - P[1] - 0.15 * MM * s
    su, tv = dx * c + dy * s, -dx * s + dy * c
    gap = (su / a) ** 2 + (tv / b) ** 2 < 1
    Q = np.array([3.4 * MM, 1.0 * MM])
    r = M.analyse_gaps(g, ~gap, np.array([P, Q]), ang, 0.15 * MM, (69e-6 / 2) ** 2)
    show(ax, g, ~gap, "(b) 45 deg layer: crack length along, width across;\ncovered stitching point")
    p0, p1 = r["points"]
    u, v = np.array([c, s]), np.array([-s, c])
    cx, cy = M.comp_xy(g, r["comps"][[k for k, cc in enumerate(r["comps"]) if cc["kind"] == "crack"][0]])
    S, T = cx * c + cy * s, -cx * s + cy * c
    lo, hi = S.min() - g.hx / 2, S.max() + g.hx / 2
    tcen = T.mean()
    A = (lo * u + (tcen - 0.25 * MM) * v) / MM
    B = (hi * u + (tcen - 0.25 * MM) * v) / MM
    arrow(ax, A, B, "r", "length L = %.3f mm" % (p0["length"] / MM), off=(30, -18))
    smid = 0.5 * (S.min() + S.max())
    sel = np.abs(S - smid) < g.hx
    t0, t1 = T[sel].min() - g.hx / 2, T[sel].max() + g.hx / 2
    for tt in (t0, t1):
        pass
    C = (smid * u + t0 * v) / MM
    D = (smid * u + t1 * v) / MM
    arrow(ax, C - 0.25 * v, C, "b")
    arrow(ax, D, D + 0.25 * v, "b")
    ax.annotate("width W = %.3f mm\n(widest station across)" % (p0["width"] / MM), tuple(C - 0.25 * v),
                xytext=(0.2, 2.4), color="b", fontsize=7,
                arrowprops=dict(arrowstyle="->", color="b", lw=0.6))
    for p, kind in ((P, p0["kind"]), (Q, p1["kind"])):
        ax.plot(p[0] / MM, p[1] / MM, "r+", ms=9)
        ax.add_patch(Circle(p / MM, 0.15, fill=False, ec="r", ls=":", lw=0.8))
    ax.annotate("covered: no gap within\nthe capture radius", Q / MM, xytext=(2.7, 0.25), color="r",
                fontsize=7, arrowprops=dict(arrowstyle="->", color="r", lw=0.6))
    ax.annotate("layer direction u", (3.0, 2.6), color="k", fontsize=7)
    ax.add_patch(FancyArrowPatch((2.6, 2.2), (2.6 + 0.4 * c, 2.2 + 0.4 * s), arrowstyle="->",
                                 mutation_scale=8, color="k"))


def panel_loop(ax):
    tilt = 14.9
    a = math.radians(tilt)
    L = 2.0
    x0, y0 = 0.6, 0.5
    x1, y1 = x0 + L * math.cos(a), y0 + L * math.sin(a)
    ax.set_title("(c) loop tilt: chord of a loop on the loop face,\nangle from x (machine direction)",
                 fontsize=9)
    ax.add_patch(Polygon([[0, 0], [3.2, 0], [3.2, 1.6], [0, 1.6]], fc="0.85", ec="none"))
    t = np.linspace(0, 1, 12)
    wig = 0.04 * np.sin(3 * math.pi * t)
    xs = x0 + t * (x1 - x0) - wig * math.sin(a)
    ys = y0 + t * (y1 - y0) + wig * math.cos(a)
    ax.plot(xs, ys, "o-", color="C3", ms=3, lw=2, label="yarn nodes beyond z_loop (one loop)")
    ax.plot([x0, x1], [y0, y1], "k--", lw=0.8, label="chord first -> last node")
    ax.plot([x0, x0 + 1.2], [y0, y0], "k-", lw=0.8)
    th = np.linspace(0, a, 20)
    ax.plot(x0 + 0.9 * np.cos(th), y0 + 0.9 * np.sin(th), "b-", lw=1)
    ax.annotate("tilt = %.1f deg" % tilt, (x0 + 0.95, y0 + 0.1), color="b", fontsize=8)
    ax.plot([x0, x1], [y0, y1], "ks", ms=4)
    ax.annotate("hole (leg)", (x0, y0), xytext=(x0 - 0.3, y0 - 0.2), fontsize=7)
    ax.annotate("next hole", (x1, y1), xytext=(x1 - 0.3, y1 + 0.12), fontsize=7)
    ax.set_xlim(0, 3.2)
    ax.set_ylim(0, 1.6)
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm] (seen on the loop face)")
    ax.set_ylabel("y [mm]")
    ax.legend(fontsize=6, loc="upper left")


def example_map(outdir):
    """doc/images/ncf-measure-example-map.png: the tool's map of a synthetic 0 deg layer (the unit
    tests' chains around an elliptical fish-eye, 2a = 1.6 mm, 2b = 0.22 mm, at one of two
    stitching points), measured through the command line."""
    import shutil
    import tempfile
    here = os.path.dirname(os.path.abspath(__file__))
    sys.path.insert(0, os.path.join(here, "..", "..", "tests", "unit"))
    import test_ncf_measure as T
    lx, ly = 4.4 * MM, 2.54 * MM
    chains = T.fisheye_layer(lx, ly, 1.1 * MM, 1.27 * MM, 0.8 * MM, 0.11 * MM)
    with tempfile.TemporaryDirectory() as tmp:
        data = os.path.join(tmp, "fisheye.data")
        T.write_data(data, (lx, ly, -1 * MM, 1 * MM), chains, 2)
        nd = os.path.join(tmp, "fisheye.needles")
        T.write_needles(nd, [(1.1 * MM, 1.27 * MM), (3.3 * MM, 1.27 * MM)])
        card = os.path.join(tmp, "fisheye.card")
        T.write_card(card, [0.0], [0.0])
        rc = M.main([data, "--needles", nd, "--card", card, "--out", tmp, "-q", "--map-range", "5"])
        if rc:
            raise SystemExit(rc)
        shutil.copy(os.path.join(tmp, "fisheye-layer1-map.png"),
                    os.path.join(outdir, "ncf-measure-example-map.png"))


def main(outdir):
    fig, axs = plt.subplots(1, 3, figsize=(15, 4.6), dpi=110)
    panel_channel(axs[0])
    panel_crack(axs[1])
    panel_loop(axs[2])
    fig.tight_layout()
    os.makedirs(outdir, exist_ok=True)
    fig.savefig(os.path.join(outdir, "ncf-measure-definitions.png"))
    example_map(outdir)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else ".")
