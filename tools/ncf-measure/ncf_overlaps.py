#!/usr/bin/env python3
"""ncf-overlaps: where the chains of a fabric data file overlap, and by how much.

The no-pass-through guards of the manufacturing stages stop a run when two chains overlap by half
a diameter. This tool lists the largest overlaps of a data file (a stage's PREFIX.STAGE.data) with
what a user needs to find the cause: the two chains' layers, the angle between the segments, and
whether each segment ends at a free chain end (a node with one bond, e.g. on an RVE face). The
overlap of two segments is d - (distance of their closest points), d the chain diameter, as the
pair style's penetration output (compute pair ncf/contact, element 3) defines it; chains of layers
of different diameters touch at the mean of the two.

    ncf-overlaps DATA (--summary PREFIX.summary | --diameter D) [--top N]

Only the chains of the fibrous layers (NCF_NODE layer >= 1) are searched. doc/ncf_measure.md.
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ncf_measure as M  # noqa: E402


def segments(data):
    """End points (p, q) of every bond between two layer nodes, q the minimum image seen from p,
    the bonds' node indices, and for each segment whether one of its nodes is a free chain end."""
    b = data.bonds
    keep = (data.layer[b[:, 0]] >= 1) & (data.layer[b[:, 1]] >= 1)
    b = b[keep]
    degree = np.bincount(data.bonds.ravel(), minlength=len(data.pos))
    p = data.pos[b[:, 0]]
    q = p + data.min_image(data.pos[b[:, 1]] - p)
    free_end = (degree[b[:, 0]] == 1) | (degree[b[:, 1]] == 1)
    return p, q, b, free_end


def closest_distance(p0, p1, q0, q1):
    """Distances of the closest points of segments p0-p1 and q0-q1 (arrays of shape (n, 3))."""
    d1, d2, r = p1 - p0, q1 - q0, p0 - q0
    a = np.einsum("ij,ij->i", d1, d1)
    e = np.einsum("ij,ij->i", d2, d2)
    f = np.einsum("ij,ij->i", d2, r)
    c = np.einsum("ij,ij->i", d1, r)
    bb = np.einsum("ij,ij->i", d1, d2)
    den = a * e - bb * bb
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(den > 1e-12 * a * e, np.clip((bb * f - c * e) / den, 0.0, 1.0), 0.0)
        t = (bb * s + f) / e
        s = np.where(t < 0.0, np.clip(-c / a, 0.0, 1.0), np.where(t > 1.0, np.clip((bb - c) / a, 0.0, 1.0), s))
        t = np.clip(t, 0.0, 1.0)
    diff = (p0 + s[:, None] * d1) - (q0 + t[:, None] * d2)
    return np.sqrt(np.einsum("ij,ij->i", diff, diff))


def overlaps(data, d_layer):
    """All pairs of segments (not sharing a node) in contact: a dict of arrays i, j (segment
    indices), overlap [m], angle [deg] between the segments, and the segments' arrays.
    d_layer: the chain diameter of each layer (a dict layer -> m)."""
    p, q, b, free_end = segments(data)
    n = len(p)
    missing = sorted(set(int(v) for v in np.unique(data.layer[b[:, 0]])) - set(d_layer))
    if missing:
        raise M.MeasureError("%s: layer(s) %s have no chain diameter" % (data.path, missing))
    dseg = np.array([d_layer[int(v)] for v in data.layer[b[:, 0]]]) if n else np.zeros(0)
    d_c = float(dseg.max()) if n else 0.0
    mid = p + 0.5 * (q - p)
    lmax = float(np.sqrt(((q - p) ** 2).sum(1)).max()) if n else 0.0
    # cells in the plane at least (longest segment + d_c) wide: a pair in contact has its
    # midpoints in the same or neighbouring cells
    reach = lmax + d_c
    nx = max(1, int(data.lx // reach))
    ny = max(1, int(data.ly // reach))
    cx = np.floor((mid[:, 0] - data.lo[0]) / data.lx * nx).astype(np.int64) % nx
    cy = np.floor((mid[:, 1] - data.lo[1]) / data.ly * ny).astype(np.int64) % ny
    cell = cx * ny + cy
    order = np.argsort(cell, kind="stable")
    start = np.searchsorted(cell[order], np.arange(nx * ny + 1))
    ii, jj = [], []
    for gx in range(nx):
        for gy in range(ny):
            a = order[start[gx * ny + gy]:start[gx * ny + gy + 1]]
            if len(a) == 0:
                continue
            nb = {((gx + dx) % nx) * ny + (gy + dy) % ny for dx in (-1, 0, 1) for dy in (-1, 0, 1)}
            for c in nb:
                o = order[start[c]:start[c + 1]]
                if len(o) == 0:
                    continue
                A, B = np.meshgrid(a, o, indexing="ij")
                m = A < B
                ii.append(A[m])
                jj.append(B[m])
    i = np.concatenate(ii) if ii else np.zeros(0, dtype=np.int64)
    j = np.concatenate(jj) if jj else np.zeros(0, dtype=np.int64)
    # no pair twice (few cells: several neighbour offsets reach the same cell), none sharing a node
    if len(i):
        key = np.unique(i * n + j)
        i, j = key // n, key % n
    share = (b[i, 0] == b[j, 0]) | (b[i, 0] == b[j, 1]) | (b[i, 1] == b[j, 0]) | (b[i, 1] == b[j, 1])
    i, j = i[~share], j[~share]
    # segment j moved to its periodic image nearest to segment i
    shift = data.min_image(mid[j] - mid[i]) - (mid[j] - mid[i])
    dist = closest_distance(p[i], q[i], p[j] + shift, q[j] + shift)
    pen = 0.5 * (dseg[i] + dseg[j]) - dist
    hit = pen > 0.0
    i, j, pen = i[hit], j[hit], pen[hit]
    u, v = q[i] - p[i], q[j] - p[j]
    cosang = np.abs(np.einsum("ij,ij->i", u, v)) / np.sqrt((u * u).sum(1) * (v * v).sum(1))
    ang = np.degrees(np.arccos(np.clip(cosang, 0.0, 1.0)))
    o = np.argsort(-pen, kind="stable")
    return {"i": i[o], "j": j[o], "overlap": pen[o], "angle": ang[o], "bonds": b,
            "free_end": free_end, "mid": mid, "d": dseg}


def report(data, d_layer, top=10, out=sys.stdout):
    """The tables of ncf-overlaps (markdown) on out; returns overlaps()'s dict. Overlaps are
    given in m and in contact distances d (the mean diameter of the two chains)."""
    r = overlaps(data, d_layer)
    fe = r["free_end"]
    rel = r["overlap"] / (0.5 * (r["d"][r["i"]] + r["d"][r["j"]])) if len(r["i"]) else r["overlap"]
    kind = fe[r["i"]].astype(int) + fe[r["j"]].astype(int)    # segments ending at a free end
    w = out.write
    w("# ncf-overlaps\n\n%s: chain diameters %s um; %d segment pairs in contact\n\n"
      % (data.path, ", ".join("layer %d: %.4g" % (k, v * 1e6) for k, v in sorted(d_layer.items())),
         len(r["i"])))
    w("| pairs | n | largest overlap [um] | [d] | above 0.3 d |\n|---|---|---|---|---|\n")
    for k, name in ((2, "both segments at a free chain end"), (1, "one at a free chain end"),
                    (0, "neither")):
        ov, rv = r["overlap"][kind == k], rel[kind == k]
        w("| %s | %d | %s | %s | %d |\n" % (name, len(ov), "%.2f" % (ov.max() * 1e6) if len(ov) else "-",
                                            "%.3f" % rv.max() if len(ov) else "-", int((rv > 0.3).sum())))
    w("\n| overlap [um] | [d] | angle [deg] | atoms A | layer A | free end A | atoms B | layer B "
      "| free end B | x, y, z of A's midpoint [mm] |\n|---|---|---|---|---|---|---|---|---|---|\n")
    ids, lay, b = data.ids, data.layer, r["bonds"]
    for k in range(min(top, len(r["i"]))):
        a, c = r["i"][k], r["j"][k]
        m = r["mid"][a] * 1e3
        w("| %.2f | %.3f | %.1f | %d-%d | %d | %s | %d-%d | %d | %s | %.3f, %.3f, %.3f |\n"
          % (r["overlap"][k] * 1e6, rel[k], r["angle"][k], ids[b[a, 0]], ids[b[a, 1]],
             lay[b[a, 0]], "yes" if fe[a] else "no", ids[b[c, 0]], ids[b[c, 1]], lay[b[c, 0]],
             "yes" if fe[c] else "no", m[0], m[1], m[2]))
    return r


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        self.print_usage(sys.stderr)
        sys.stderr.write("ncf-overlaps: error: %s\n" % message)
        sys.exit(2)


def _diameter(text):
    """A chain diameter: a number, optionally with a unit m, mm, um (metres without one); a
    leading minus is read here too, so that argparse does not take '-69e-6' for an option."""
    try:
        return M._length_text(text)
    except ValueError as e:
        raise argparse.ArgumentTypeError(str(e))


def _top(text):
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError("'%s' is not an integer" % text)
    return v


def main(argv=None):
    argv = M.join_negative_values(sys.argv[1:] if argv is None else list(argv), ("--diameter", "--top"))
    p = _Parser(prog="ncf-overlaps", description=__doc__.split("\n\n")[0])
    p.add_argument("data", help="LAMMPS data file with NCF_NODE (a stage's PREFIX.STAGE.data)")
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--summary", help="the generator's PREFIX.summary (chain diameter)")
    src.add_argument("--diameter", type=_diameter,
                     help="chain diameter [m] (or with a unit: 69 um), 1 um to 5 mm")
    p.add_argument("--top", type=_top, default=10, help="pairs listed (default 10)")
    args = p.parse_args(argv)
    try:
        if args.top < 0:
            raise M.MeasureError("--top %d: must be >= 0" % args.top)
        if args.diameter is not None and not (1e-6 <= args.diameter <= 5e-3):
            # (a chain of a fabric is tens to hundreds of micrometres: 69 is metres, not um)
            raise M.MeasureError("--diameter %g m: must be between 1 um and 5 mm (a value in "
                                 "micrometres needs its unit: 69 um)" % args.diameter)
        data = M.read_data(args.data)
        if args.summary:
            d_layer = {L.index: L.d_c for L in M.read_summary(args.summary).layers}
        else:
            d_layer = {int(v): args.diameter for v in np.unique(data.layer) if v >= 1}
        report(data, d_layer, args.top)
    except M.MeasureError as e:
        print("ncf-overlaps: error: %s" % e, file=sys.stderr)
        return 2
    except (OSError, ValueError, IndexError, KeyError) as e:
        print("ncf-overlaps: error: %s" % M.describe_error(e), file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
