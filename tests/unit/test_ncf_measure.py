#!/usr/bin/python3
"""Unit tests of tools/ncf-measure (doc/ncf_measure.md) on synthetic layers with known answers.

Every synthetic layer is written as a LAMMPS data file (atom_style bond, NCF_NODE) and measured
through the same functions the command line uses; lengths must come out exact to the map's
resolution. Files go to a temporary folder under $NCF_BUILD (or the system's temp folder), never
into the source tree. Run: python3 -B tests/unit/test_ncf_measure.py (ctest: unit.ncf_measure).
"""

import io
import math
import os
import sys
import tempfile
import unittest
from contextlib import redirect_stderr, redirect_stdout

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.environ.get("NCF_ROOT", os.path.normpath(os.path.join(HERE, "..", "..")))
sys.path.insert(0, os.path.join(ROOT, "tools", "ncf-measure"))
import ncf_measure as M  # noqa: E402

MM = 1e-3
UM = 1e-6
D = 69 * UM          # chain contact diameter of the synthetic layers
H = 5 * UM           # map resolution of the tests


def tmpdir():
    base = os.environ.get("NCF_BUILD")
    if base and os.path.isdir(base):
        os.makedirs(os.path.join(base, "tmp-tests"), exist_ok=True)
        return tempfile.TemporaryDirectory(dir=os.path.join(base, "tmp-tests"))
    return tempfile.TemporaryDirectory()


# ----------------------------------------------------------------------------- synthetic files

class Chain:
    def __init__(self, nodes, layer, closed=False, ends=None):
        self.nodes = np.asarray(nodes, float)   # unwrapped positions (n, 3)
        self.layer = layer                      # 0 = yarn
        self.closed = closed                    # bond from the last node back to the first
        self.ends = ends or {}                  # node index -> NCF_NODE end code


def write_data(path, box, chains, ntypes, skip_node_section=False, style_comment="bond"):
    lx, ly = box[0], box[1]
    zlo, zhi = box[2], box[3]
    atoms, bonds, node = [], [], []
    tag = 0
    for c, ch in enumerate(chains, 1):
        first = tag + 1
        typ = ch.layer if ch.layer > 0 else ntypes
        for k, p in enumerate(ch.nodes):
            tag += 1
            ix, iy = math.floor(p[0] / lx), math.floor(p[1] / ly)
            atoms.append("%d %d %d %.17g %.17g %.17g %d %d 0"
                         % (tag, c, typ, p[0] - ix * lx, p[1] - iy * ly, p[2], ix, iy))
            node.append("%d %d %d" % (tag, ch.layer, ch.ends.get(k, 0)))
            if k > 0:
                bonds.append((typ, tag - 1, tag))
        if ch.closed:
            bonds.append((typ, tag, first))
    s = ["LAMMPS data file: synthetic test layer", "",
         "%d atoms" % len(atoms), "%d atom types" % ntypes, "%d bonds" % len(bonds),
         "%d bond types" % ntypes, "",
         "0 %.17g xlo xhi" % lx, "0 %.17g ylo yhi" % ly, "%.17g %.17g zlo zhi" % (zlo, zhi), "",
         "Masses", ""] + ["%d 1e-9" % t for t in range(1, ntypes + 1)] + \
        ["", "Atoms # %s" % style_comment, ""] + atoms + ["", "Bonds", ""] + \
        ["%d %d %d %d" % (k + 1, b[0], b[1], b[2]) for k, b in enumerate(bonds)]
    if not skip_node_section:
        s += ["", "NCF_NODE", ""] + node
    with open(path, "w") as f:
        f.write("\n".join(s) + "\n")


def write_needles(path, pts):
    with open(path, "w") as f:
        f.write("# synthetic stitching points\n")
        for p in pts:
            f.write("%.17g %.17g\n" % tuple(p))


def write_card(path, angles, sigmas=None, loops="bottom"):
    sigmas = sigmas or [0.0] * len(angles)
    with open(path, "w") as f:
        f.write("name synthetic\nchain_diameter %g um\n" % (D / UM))
        for a, s in zip(angles, sigmas):
            f.write("layer %r deg\n  sigma %r deg\n" % (a, s))
        f.write("loops %s\n" % loops)


def straight(x0, y0, x1, y1, z, step=0.1 * MM, include_end=True):
    n = max(1, int(math.ceil(math.hypot(x1 - x0, y1 - y0) / step)))
    t = np.linspace(0, 1, n + 1) if include_end else np.linspace(0, 1, n + 1)[:-1]
    return np.stack([x0 + t * (x1 - x0), y0 + t * (y1 - y0), np.full_like(t, z)], 1)


def x_chain(y, lx, z=0.1 * MM, step=0.1 * MM, x0=0.0):
    """A straight periodic chain along x at height y (closed through the x faces)."""
    return Chain(straight(x0, y, x0 + lx, y, z, step, include_end=False), 1, closed=True)


def offset_ellipse(a, b, d, upper=True, n=4000):
    """Nodes of the curve parallel to the ellipse (x/a)^2 + (y/b)^2 = 1 at distance d/2 outside
    it, upper or lower half, from the left tip to the right tip."""
    phi = np.linspace(math.pi, 0.0, n) if upper else np.linspace(math.pi, 2 * math.pi, n)
    ex, ey = a * np.cos(phi), b * np.sin(phi)
    nx, ny = b * np.cos(phi), a * np.sin(phi)
    nn = np.hypot(nx, ny)
    return ex + 0.5 * d * nx / nn, ey + 0.5 * d * ny / nn


def fisheye_layer(lx, ly, xc, yc, a, b, d=D, spacing=None, z=0.1 * MM, layer=1):
    """Chains along x, spacing d/3, that part around an elliptical gap of half-axes a (along x)
    and b centred at (xc, yc): the chains that would cross it follow the curve parallel to the
    ellipse at d/2, so the uncovered region is the ellipse (up to the chords of a polyline with
    ~1 um steps)."""
    spacing = spacing or d / 3
    n = int(round(ly / spacing))
    s = ly / n
    ux, uy = offset_ellipse(a, b, d, True)
    lxs, lys = offset_ellipse(a, b, d, False)
    chains = []
    for k in range(n):
        yk = (k + 0.5) * s
        dy = yk - yc
        dy -= ly * round(dy / ly)           # the chain's height relative to the ellipse centre
        y = yc + dy
        cx, cy = (ux, uy) if dy >= 0 else (lxs, lys)
        inside = (cy >= dy) if dy >= 0 else (cy <= dy)
        if not inside.any():
            chains.append(Chain(straight(xc - lx / 2, y, xc + lx / 2, y, z, include_end=False),
                                layer, closed=True))
            continue
        idx = np.nonzero(inside)[0]
        i0, i1 = idx[0], idx[-1]
        # junctions on the polyline where it crosses height dy
        def cross(i, j):
            t = (dy - cy[i]) / (cy[j] - cy[i]) if cy[j] != cy[i] else 0.0
            return cx[i] + t * (cx[j] - cx[i])
        xl = cross(i0 - 1, i0) if i0 > 0 else cx[0]
        xr = cross(i1, i1 + 1) if i1 < len(cx) - 1 else cx[-1]
        left = straight(xc - lx / 2, y, xc + xl, y, z)
        mid = np.stack([xc + cx[i0:i1 + 1], yc + cy[i0:i1 + 1], np.full(i1 - i0 + 1, z)], 1)
        right = straight(xc + xr, y, xc + lx / 2, y, z, include_end=False)
        chains.append(Chain(np.concatenate([left, mid, right]), layer, closed=True))
    return chains


def measure(tmp, box, chains, needles, angles, layer=1, ntypes=None, **kw):
    path = os.path.join(tmp, "layer.data")
    write_data(path, box, chains, ntypes or len(angles) + 1)
    data = M.read_data(path)
    fab = M.Fabric("test")
    fab.layers = [M.LayerInfo(i + 1, a, 0.0, D) for i, a in enumerate(angles)]
    L = fab.layer(layer)
    return data, M.measure_layer(data, fab, L, np.asarray(needles, float), kw.get("h", H),
                                 kw.get("capture", 0.15 * MM), kw.get("min_area", (D / 2) ** 2),
                                 kw.get("search", 0.3 * MM))


def run_cli(argv):
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        try:
            rc = M.main(argv)
        except SystemExit as e:
            rc = e.code
    return rc, out.getvalue(), err.getvalue()


# ----------------------------------------------------------------------------- tests

class Orientation(unittest.TestCase):
    def test_known_angles_length_weighted(self):
        """Chains at +10 deg (length 3 mm) and -20 deg (length 1 mm) in a 0 deg layer: the
        length-weighted mean is (3*10 - 20)/4 = 2.5 deg, SD sqrt((3*7.5^2 + 22.5^2)/4)."""
        with tmpdir() as tmp:
            box = (10 * MM, 10 * MM, -1 * MM, 1 * MM)
            c1 = straight(1 * MM, 1 * MM, 1 * MM + 3 * MM * math.cos(math.radians(10)),
                          1 * MM + 3 * MM * math.sin(math.radians(10)), 0.0, step=0.07 * MM)
            c2 = straight(2 * MM, 6 * MM, 2 * MM + 1 * MM * math.cos(math.radians(-20)),
                          6 * MM + 1 * MM * math.sin(math.radians(-20)), 0.0, step=0.13 * MM)
            p = os.path.join(tmp, "o.data")
            write_data(p, box, [Chain(c1, 1), Chain(c2, 1)], 2)
            dev, w = M.layer_orientation(M.read_data(p), 1, 0.0)
            m, s = M.weighted_stats(dev, w)
            self.assertAlmostEqual(m, 2.5, places=9)
            self.assertAlmostEqual(s, math.sqrt((3 * 7.5 ** 2 + 22.5 ** 2) / 4), places=9)
            self.assertAlmostEqual(float(np.sum(w)), 4 * MM, places=12)

    def test_atom_style_angle_reads_as_bond(self):
        """A 'bending bundle' layer (atom_style angle: 'Atoms # angle', an Angles section and
        angle counts in the header) measures as the same layer written as atom_style bond."""
        with tmpdir() as tmp:
            box = (10 * MM, 10 * MM, -1 * MM, 1 * MM)
            c1 = straight(1 * MM, 1 * MM, 4 * MM, 2 * MM, 0.0, step=0.07 * MM)
            c2 = straight(2 * MM, 6 * MM, 7 * MM, 5 * MM, 0.0, step=0.13 * MM)
            pb, pa = os.path.join(tmp, "b.data"), os.path.join(tmp, "a.data")
            write_data(pb, box, [Chain(c1, 1), Chain(c2, 1)], 2)
            write_data(pa, box, [Chain(c1, 1), Chain(c2, 1)], 2, style_comment="angle")
            text = open(pa).read()
            n1, n2 = len(c1), len(c2)
            angles = ["%d 1 %d %d %d" % (k + 1, t - 1, t, t + 1) for k, t in
                      enumerate(list(range(2, n1)) + list(range(n1 + 2, n1 + n2)))]
            text = text.replace("bond types\n", "bond types\n%d angles\n1 angle types\n"
                                % len(angles))
            text = text.replace("\nNCF_NODE\n", "\nAngles\n\n" + "\n".join(angles) +
                                "\n\nNCF_NODE\n")
            open(pa, "w").write(text)
            a, b = M.read_data(pa), M.read_data(pb)
            np.testing.assert_array_equal(a.pos, b.pos)
            np.testing.assert_array_equal(a.bonds, b.bonds)
            self.assertEqual(len(a.bonds), n1 + n2 - 2)
            np.testing.assert_array_equal(M.layer_orientation(a, 1, 0.0)[0],
                                          M.layer_orientation(b, 1, 0.0)[0])

    def test_wrap_past_90_and_reversed_chain(self):
        """A 90 deg layer: a chain at -85 deg (= 95 deg as an axis) deviates by +5 deg, a chain
        at 84 deg written backwards by -6 deg; nothing lands near +-180."""
        with tmpdir() as tmp:
            box = (10 * MM, 10 * MM, -1 * MM, 1 * MM)
            a = math.radians(-85)
            c1 = straight(5 * MM, 8 * MM, 5 * MM + 2 * MM * math.cos(a), 8 * MM + 2 * MM * math.sin(a), 0)
            b = math.radians(84)
            c2 = straight(2 * MM, 1 * MM, 2 * MM + 2 * MM * math.cos(b), 1 * MM + 2 * MM * math.sin(b), 0)[::-1]
            p = os.path.join(tmp, "o.data")
            write_data(p, box, [Chain(c1, 1), Chain(c2, 1)], 2)
            dev, w = M.layer_orientation(M.read_data(p), 1, 90.0)
            n1 = len(c1) - 1
            np.testing.assert_allclose(dev[:n1], 5.0, atol=1e-9)
            np.testing.assert_allclose(dev[n1:], -6.0, atol=1e-9)
        self.assertEqual(float(M.wrap_deviation(-90.0)), 90.0)
        self.assertEqual(float(M.wrap_deviation(270.0)), 90.0)
        self.assertAlmostEqual(float(M.wrap_deviation(179.0)), -1.0)

    def test_periodic_crossing(self):
        """A chain at 30 deg crossing the x and y faces several times (written wrapped, with
        image flags): every bond has the chain's angle (minimum image), none is a box length long."""
        with tmpdir() as tmp:
            box = (2 * MM, 1.5 * MM, -1 * MM, 1 * MM)
            a = math.radians(30)
            c = straight(1.5 * MM, 1.2 * MM, 1.5 * MM + 6 * MM * math.cos(a),
                         1.2 * MM + 6 * MM * math.sin(a), 0, step=0.2 * MM)
            p = os.path.join(tmp, "o.data")
            write_data(p, box, [Chain(c, 1)], 2)
            data = M.read_data(p)
            self.assertTrue(np.all(data.pos[:, 0] < 2 * MM) and np.all(data.pos[:, 1] < 1.5 * MM))
            dev, w = M.layer_orientation(data, 1, 20.0)
            np.testing.assert_allclose(dev, 10.0, atol=1e-9)
            self.assertAlmostEqual(float(np.sum(w)), 6 * MM, places=12)

    def test_density_integrates_to_one(self):
        rng = np.random.default_rng(3)
        x = rng.normal(0, 2, 5000)
        w = rng.uniform(0.5, 1.5, 5000)
        e, dns = M.density(x, w, 60, 15.0)
        self.assertAlmostEqual(float(np.sum(dns) * (e[1] - e[0])), 1.0, places=9)


class Raster(unittest.TestCase):
    def test_capsule_exact(self):
        """A pixel is covered iff its centre is within d/2 of the segment (brute force), also
        for a segment across the periodic corner."""
        g = M.Grid(0.0, 0.0, 1 * MM, 0.8 * MM, 7 * UM)
        a = np.array([[0.95 * MM, 0.75 * MM]])
        b = np.array([[1.23 * MM, 0.91 * MM]])   # unwrapped, beyond the corner
        cov = M.rasterize(g, a, b, 0.5 * D)
        x, y = g.centres()
        X, Y = np.meshgrid(x, y)
        ref = np.zeros_like(cov)
        for sx in (-1, 0, 1):
            for sy in (-1, 0, 1):
                px, py = X + sx * g.lx, Y + sy * g.ly
                e = b[0] - a[0]
                t = np.clip(((px - a[0, 0]) * e[0] + (py - a[0, 1]) * e[1]) / e.dot(e), 0, 1)
                ref |= np.hypot(px - a[0, 0] - t * e[0], py - a[0, 1] - t * e[1]) <= 0.5 * D
        self.assertGreater(int(ref.sum()), 100)
        np.testing.assert_array_equal(cov, ref)

    def test_deviation_map_sees_the_face(self):
        """Two chains crossing at different heights (+5 deg at z = 0.1 mm, -3 deg at z = 0.3 mm):
        at the crossing, the map seen from the top shows -3, seen from the bottom +5."""
        with tmpdir() as tmp:
            box = (4 * MM, 4 * MM, -1 * MM, 1 * MM)
            def chain(deg, z):
                a = math.radians(deg)
                return Chain(straight(2 * MM - 1.5 * MM * math.cos(a), 2 * MM - 1.5 * MM * math.sin(a),
                                      2 * MM + 1.5 * MM * math.cos(a), 2 * MM + 1.5 * MM * math.sin(a),
                                      z), 1)
            p = os.path.join(tmp, "z.data")
            write_data(p, box, [chain(5.0, 0.1 * MM), chain(-3.0, 0.3 * MM)], 2)
            data = M.read_data(p)
            g = M.Grid.of(data, H)
            i, j = int(2 * MM / g.hx), int(2 * MM / g.hy)
            for top, want in ((True, -3.0), (False, 5.0)):
                cov, dev = M.coverage(data, g, 1, 0.0, D, top=top)
                self.assertTrue(cov[j, i])
                self.assertAlmostEqual(float(dev[j, i]), want, places=9)
                self.assertTrue(np.isnan(dev[~cov]).all())

    def test_periodic_labelling(self):
        """A band through the x faces is one component that wraps; a blob on the corner is one
        component whose unwrapped extent is its true size."""
        gap = np.zeros((40, 60), bool)
        gap[10:14, :] = True              # band along x through the whole box
        gap[:3, :2] = True                # blob on the four corners
        gap[-3:, :2] = True
        gap[:3, -2:] = True
        gap[-3:, -2:] = True
        lab, comps = M.label_periodic(gap)
        self.assertEqual(len(comps), 2)
        band = [c for c in comps if len(c["i"]) == 4 * 60][0]
        self.assertEqual(band["wraps"], (True, False))
        blob = [c for c in comps if len(c["i"]) == 24][0]
        self.assertEqual(blob["wraps"], (False, False))
        x = blob["i"] + blob["sx"] * 60
        y = blob["j"] + blob["sy"] * 40
        self.assertEqual(int(x.max() - x.min()), 3)
        self.assertEqual(int(y.max() - y.min()), 5)


class Defects(unittest.TestCase):
    def test_straight_channel(self):
        """0 deg layer: chains along x, spacing d/3, with one missing band: the uncovered channel
        is W = 0.31 mm wide (edge-to-edge of the chains on its sides); every stitching point on
        the channel line is on a channel and the width in the middle between them is W."""
        lx, ly = 11.2 * MM, 5.08 * MM
        W = 0.31 * MM
        yc = 2.0021 * MM        # off the pixel edges
        s = D / 3
        ys = [yc - W / 2 - D / 2 - k * s for k in range(int((ly - W - D) / s) + 1)]
        ys = [y for y in ys if y > yc + W / 2 + D / 2 - ly]
        chains = [x_chain(y % ly, lx) for y in ys] + [x_chain(yc + W / 2 + D / 2, lx)]
        needles = [((c + 0.5) * 2.8 * MM, yc) for c in range(4)]
        with tmpdir() as tmp:
            data, r = measure(tmp, (lx, ly, -1 * MM, 1 * MM), chains, needles, [0.0, 90.0])
        self.assertEqual([p["kind"] for p in r["points"]], ["channel"] * 4)
        self.assertEqual(len(r["channels"]), 4)
        np.testing.assert_allclose(r["channel_vector"], [2.8 * MM, 0.0], atol=1e-12)
        for c in r["channels"]:
            self.assertLessEqual(abs(c["width"] - W), 0.5 * r["grid"].hy, c)
            dx = c["x"] - (needles[c["index"]][0] + 1.4 * MM)
            self.assertAlmostEqual(dx - lx * round(dx / lx), 0.0, delta=1e-9)   # the middle, in the box
            self.assertTrue(0 <= c["x"] < lx)
        # a chain crossing the channel at 10 deg through the middle of the first two stitching
        # points: there the line across holds two open runs, W - d/cos(10 deg) together
        phi = math.radians(10.0)
        M0 = np.array([needles[0][0] + 1.4 * MM, yc])
        cross = straight(M0[0] - 1.5 * MM * math.cos(phi), yc - 1.5 * MM * math.sin(phi),
                         M0[0] + 1.5 * MM * math.cos(phi), yc + 1.5 * MM * math.sin(phi), 0.2 * MM,
                         step=0.1 * MM)
        with tmpdir() as tmp:
            _, r3 = measure(tmp, (lx, ly, -1 * MM, 1 * MM), chains + [Chain(cross, 1)], needles,
                            [0.0, 90.0])
        w3 = {c["index"]: c["width"] for c in r3["channels"]}
        self.assertLessEqual(abs(w3[0] - (W - D / math.cos(phi))), r3["grid"].hy, w3)
        for k in (1, 2, 3):
            self.assertLessEqual(abs(w3[k] - W), 0.5 * r3["grid"].hy, w3)
        # a narrower channel of the same layer reads narrower: the width is measured, not assumed
        chains2 = chains + [x_chain(yc + W / 2 + D / 2 - 0.05 * MM, lx)]
        with tmpdir() as tmp:
            _, r2 = measure(tmp, (lx, ly, -1 * MM, 1 * MM), chains2, needles, [0.0, 90.0])
        for c in r2["channels"]:
            self.assertLessEqual(abs(c["width"] - (W - 0.05 * MM)), 0.5 * r2["grid"].hy)

    def check_fisheye(self, xc, yc, lx=4.4 * MM, ly=5.08 * MM, a=1.2 * MM, b=0.11 * MM):
        chains = fisheye_layer(lx, ly, xc, yc, a, b)
        needles = [(xc % lx, yc % ly), ((xc + lx / 2) % lx, (yc + ly / 2) % ly)]
        with tmpdir() as tmp:
            data, r = measure(tmp, (lx, ly, -1 * MM, 1 * MM), chains, needles, [0.0, 90.0])
        p0, p1 = r["points"]
        self.assertEqual(p0["kind"], "crack")
        # 2a and 2b are whole numbers of pixels: exact to half a pixel (a pixel in general)
        self.assertLessEqual(abs(p0["length"] - 2 * a), 0.5 * r["grid"].hx, p0)
        self.assertLessEqual(abs(p0["width"] - 2 * b), 0.5 * r["grid"].hy, p0)
        self.assertEqual(p1["kind"], "covered")
        self.assertEqual([c["kind"] for c in r["comps"] if c["kind"] != "small"], ["crack"])
        return r

    def test_fisheye(self):
        """An elliptical fish-eye (length 2.4 mm, width 0.22 mm) at a stitching point: one crack
        of that length and width; the other stitching point is covered."""
        self.check_fisheye(2.2 * MM, 2.54 * MM)

    def test_fisheye_across_periodic_corner(self):
        """The same fish-eye centred near the corner of the box (crosses the x and the y faces):
        the same length and width."""
        self.check_fisheye(0.3013 * MM, 5.0037 * MM)

    def test_fisheye_in_45deg_layer_mask(self):
        """Mask level, oblique: an ellipse along 45 deg (2a = 2.0 mm, 2b = 0.2 mm) in a 45 deg
        layer; length and width to one pixel diagonal."""
        g = M.Grid(0.0, 0.0, 4.4 * MM, 5.08 * MM, H)
        x, y = g.centres()
        X, Y = np.meshgrid(x, y)
        a, b = 1.0 * MM, 0.1 * MM
        c = math.sqrt(0.5)
        for xc, yc in ((2.2 * MM, 2.5 * MM), (4.3 * MM, 0.2 * MM)):
            dx, dy = X - xc, Y - yc
            dx -= g.lx * np.round(dx / g.lx)
            dy -= g.ly * np.round(dy / g.ly)
            s, t = dx * c + dy * c, -dx * c + dy * c
            covered = (s / a) ** 2 + (t / b) ** 2 > 1
            r = M.analyse_gaps(g, covered, np.array([[xc, yc]]), 45.0, 0.15 * MM, (D / 2) ** 2)
            p = r["points"][0]
            self.assertEqual(p["kind"], "crack")
            self.assertLessEqual(abs(p["length"] - 2 * a), math.hypot(g.hx, g.hy), p)
            self.assertLessEqual(abs(p["width"] - 2 * b), math.hypot(g.hx, g.hy), p)

    def test_gap_joining_two_points_is_a_channel(self):
        """Mask level, 45 deg layer whose direction joins no stitching points: a gap from one
        stitching point to the other (along 31 deg) is a channel at both, not two cracks."""
        g = M.Grid(0.0, 0.0, 4.4 * MM, 5.08 * MM, H)
        P, Q = np.array([1.0 * MM, 1.0 * MM]), np.array([2.0 * MM, 1.6 * MM])
        x, y = g.centres()
        X, Y = np.meshgrid(x, y)
        e = Q - P
        t = np.clip(((X - P[0]) * e[0] + (Y - P[1]) * e[1]) / e.dot(e), 0, 1)
        gap = np.hypot(X - P[0] - t * e[0], Y - P[1] - t * e[1]) < 0.05 * MM
        r = M.analyse_gaps(g, ~gap, np.array([P, Q]), 45.0, 0.15 * MM, (D / 2) ** 2)
        self.assertIsNone(r["channel_vector"])
        self.assertEqual([p["kind"] for p in r["points"]], ["channel", "channel"])
        self.assertEqual([c["kind"] for c in r["comps"]], ["channel"])

    def test_gap_near_or_far_from_a_channel_line(self):
        """Mask level, 0 deg layer with stitching points every 2.8 mm along x: a gap 0.1 mm off
        the line between two of them (and far from both) is a piece of the channel, a gap 1 mm
        off it (beyond the 0.3 mm search) is an other gap assigned to the nearest point."""
        g = M.Grid(0.0, 0.0, 5.6 * MM, 5.08 * MM, H)
        x, y = g.centres()
        X, Y = np.meshgrid(x, y)
        yc = 2.54 * MM
        needles = np.array([[1.4 * MM, yc], [4.2 * MM, yc]])
        near = (np.abs(X - 2.8 * MM) < 0.1 * MM) & (np.abs(Y - (yc + 0.1 * MM)) < 0.03 * MM)
        far = (np.abs(X - 3.5 * MM) < 0.1 * MM) & (np.abs(Y - (yc - 1.0 * MM)) < 0.03 * MM)
        r = M.analyse_gaps(g, ~(near | far), needles, 0.0, 0.15 * MM, (D / 2) ** 2, 0.3 * MM)
        kinds = {}
        for c in r["comps"]:
            cy = np.mean(M.comp_xy(g, c)[1])
            kinds["near" if cy > yc else "far"] = (c["kind"], c["needle"])
        self.assertEqual(kinds["near"][0], "channel")
        self.assertEqual(kinds["far"], ("gap", 1))
        self.assertEqual([p["kind"] for p in r["points"]], ["covered", "covered"])
        # the channel piece opens the middle between the points (x = 2.8 mm), 0.06 mm wide
        w = {round(c["x"] / MM, 3): c["width"] for c in r["channels"]}
        self.assertLessEqual(abs(w[2.8] - 0.06 * MM), 0.5 * g.hy)
        self.assertEqual(w[0.0], 0.0)

    def test_covered_stitching_point(self):
        """A closed 0 deg layer (chains at d/3): no gap at all; every stitching point is covered
        (share without a visible crack 100 %), and there is no open channel."""
        lx, ly = 4.4 * MM, 2.0 * MM
        n = int(round(ly / (D / 3)))
        chains = [x_chain((k + 0.5) * ly / n, lx) for k in range(n)]
        needles = [(1.1 * MM, 1.0 * MM), (3.3 * MM, 1.0 * MM)]
        with tmpdir() as tmp:
            data, r = measure(tmp, (lx, ly, -1 * MM, 1 * MM), chains, needles, [0.0])
        self.assertTrue(r["covered"].all())
        self.assertEqual([p["kind"] for p in r["points"]], ["covered", "covered"])
        self.assertEqual([c["width"] for c in r["channels"]], [0.0, 0.0])

    def test_chain_ends_close_the_main_faces(self):
        """Chains along x that end half an element inside the x faces (averaged PBC, no bond
        across the face, end codes 1/2) still cover the face: the tool extends each end by half
        its last element; without the end codes the faces read as a gap."""
        lx, ly = 2.0 * MM, 1.0 * MM
        n = int(round(ly / (D / 3)))
        chains = []
        for k in range(n):
            y = (k + 0.5) * ly / n
            nodes = straight(0.1 * MM, y, lx - 0.1 * MM, y, 0.0, step=0.2 * MM)
            chains.append(Chain(nodes, 1, ends={0: 1, len(nodes) - 1: 2}))
        with tmpdir() as tmp:
            data, r = measure(tmp, (lx, ly, -1 * MM, 1 * MM), chains, [(1 * MM, 0.5 * MM)], [0.0])
        self.assertTrue(r["covered"].all())
        for c in chains:
            c.ends = {}
        with tmpdir() as tmp:
            data, r = measure(tmp, (lx, ly, -1 * MM, 1 * MM), chains, [(1 * MM, 0.5 * MM)], [0.0])
        self.assertFalse(r["covered"].all())


class Loops(unittest.TestCase):
    def test_loop_tilt(self):
        """Two yarn loops on the bottom face, tilted by +12.5 and -7 deg from x (the second one
        across the periodic x face): the tilts come out exactly, the underlaps on top are not
        loops."""
        lx, ly = 4.4 * MM, 5.08 * MM
        zb, zt = -0.04 * MM, 0.9 * MM
        chains = [x_chain(y, lx, z=0.2 * MM) for y in (1 * MM, 3 * MM)]
        chains += [Chain(c.nodes + [0, 0.5 * MM, 0.4 * MM], 2, closed=True) for c in chains]

        def yarn(x0, y0, tilt, length):
            a = math.radians(tilt)
            x1, y1 = x0 + length * math.cos(a), y0 + length * math.sin(a)
            legd = straight(x0, y0, x0, y0, 0)[:1]
            down = np.array([[x0, y0, z] for z in np.linspace(zt, zb, 8)])
            loop = straight(x0, y0, x1, y1, zb, step=0.1 * MM)[1:]
            up = np.array([[x1, y1, z] for z in np.linspace(zb, zt, 8)])[1:]
            back = straight(x1, y1, x0, y0, zt, step=0.1 * MM)[1:-1]
            del legd
            return Chain(np.concatenate([down, loop, up, back]), 0, closed=True)

        chains += [yarn(1.0 * MM, 1.5 * MM, 12.5, 2.1 * MM), yarn(3.9 * MM, 4.0 * MM, -7.0, 2.1 * MM)]
        with tmpdir() as tmp:
            p = os.path.join(tmp, "y.data")
            write_data(p, (lx, ly, -1 * MM, 2 * MM), chains, 3)
            data = M.read_data(p)
            fab = M.Fabric("t")
            fab.layers = [M.LayerInfo(1, 0.0), M.LayerInfo(2, 90.0)]
            zthr, loops = M.loop_tilts(data, fab)
        self.assertAlmostEqual(zthr, 0.2 * MM)
        self.assertEqual(len(loops), 2)
        tilts = sorted(l["tilt"] for l in loops)
        self.assertAlmostEqual(tilts[0], -7.0, places=9)
        self.assertAlmostEqual(tilts[1], 12.5, places=9)
        for l in loops:
            self.assertAlmostEqual(l["chord"], 2.1 * MM, places=12)

    def test_knitted_loop_tilt_from_hole_to_head(self):
        """Knitted loops (both legs through one hole, out and back on the bottom face with a head
        across, as ncf-gen's warp knit), their axes tilted by +14 and -9 deg from x (the second
        across the periodic x face), the legs side by side along the axis so that the two sides
        differ in length: the tilt is that of the axis, exactly, and the chord the loop's extent
        along it."""
        lx, ly = 4.4 * MM, 5.08 * MM
        zb, zt = -0.04 * MM, 0.9 * MM
        chains = [x_chain(y, lx, z=0.2 * MM) for y in (1 * MM, 3 * MM)]
        chains += [Chain(c.nodes + [0, 0.5 * MM, 0.4 * MM], 2, closed=True) for c in chains]
        e, g, reach = 0.05 * MM, 0.1 * MM, 2.5 * MM

        def knit(x0, y0, tilt):
            a = math.radians(tilt)
            u = np.array([math.cos(a), math.sin(a)])          # along the loop's axis
            v = np.array([-math.sin(a), math.cos(a)])         # across it
            h = np.array([x0, y0])
            pts = [h - e * u, h - e * u - g * v, h + reach * u - g * v, h + reach * u + g * v,
                   h + e * u + g * v, h + e * u]
            down = np.array([[*pts[0], z] for z in np.linspace(zt, zb, 8)])
            loop = [down]
            for p0, p1 in zip(pts[:-1], pts[1:]):
                loop.append(straight(p0[0], p0[1], p1[0], p1[1], zb, step=0.05 * MM)[1:])
            up = np.array([[*pts[-1], z] for z in np.linspace(zb, zt, 8)])[1:]
            back = straight(pts[-1][0], pts[-1][1], pts[0][0], pts[0][1], zt, step=0.02 * MM)[1:-1]
            return Chain(np.concatenate(loop + [up, back]), 0, closed=True)

        chains += [knit(1.0 * MM, 1.5 * MM, 14.0), knit(3.9 * MM, 4.0 * MM, -9.0)]
        with tmpdir() as tmp:
            p = os.path.join(tmp, "k.data")
            write_data(p, (lx, ly, -1 * MM, 2 * MM), chains, 3)
            data = M.read_data(p)
            fab = M.Fabric("t")
            fab.layers = [M.LayerInfo(1, 0.0), M.LayerInfo(2, 90.0)]
            _, loops = M.loop_tilts(data, fab)
        self.assertEqual(len(loops), 2)
        tilts = sorted(l["tilt"] for l in loops)
        self.assertAlmostEqual(tilts[0], -9.0, places=9)
        self.assertAlmostEqual(tilts[1], 14.0, places=9)
        for l in loops:
            self.assertAlmostEqual(l["chord"], reach + e, places=12)


class Summary(unittest.TestCase):
    def test_yarn_diameter_in_both_summary_formats(self):
        # the generator's summary names the yarn's packing ("chain diameter, packing"); summaries
        # of earlier versions said "chain diameter (hexagonal packing)": both give the diameter
        src = os.path.join(ROOT, "examples", "gen-ncf45", "ncf45.summary")
        with open(src) as f:
            text = f.read()
        self.assertIn("chain diameter, packing             71.32 um, 0.9069", text)
        old = text.replace("chain diameter, packing             71.32 um, 0.9069",
                           "chain diameter (hexagonal packing)  71.32 um")
        with tmpdir() as tmp:
            p = os.path.join(tmp, "old.summary")
            with open(p, "w") as f:
                f.write(old)
            for path in (src, p):
                fab = M.read_summary(path)
                self.assertAlmostEqual(fab.yarn_d, 71.32e-6, delta=1e-12)
                self.assertEqual([L.angle for L in fab.layers], [-45.0, 45.0])


class Overlaps(unittest.TestCase):
    """ncf-overlaps on a scene of known overlaps: two chains of layer 1 whose free ends come
    within 40 um across a periodic face (overlap d - 40 um, both at a free end, 30 deg apart) and
    a periodic chain of layer 2 crossing the first one's interior 10 um too low (overlap 10 um,
    neither)."""

    def scene(self, tmp):
        L = 2 * MM
        # (the end segments of A and B straddle the periodic face x = L)
        a = Chain(straight(0.63 * MM, 1.0 * MM, 2.03 * MM, 1.0 * MM, 0.1 * MM), 1)
        c30, s30 = math.cos(math.radians(30)), math.sin(math.radians(30))
        b = Chain(straight(2.03 * MM, 1.04 * MM, 2.03 * MM - 0.5 * MM * c30,
                           1.04 * MM + 0.5 * MM * s30, 0.1 * MM), 1)
        # (crossing A and crossed by A in the middle of a segment each)
        c = Chain(straight(1.18 * MM, 0.05 * MM, 1.18 * MM, L + 0.05 * MM, 0.1 * MM + D - 10 * UM,
                           include_end=False), 2, closed=True)
        path = os.path.join(tmp, "ov.data")
        write_data(path, (L, L, -1 * MM, 1 * MM), [a, b, c], 2)
        return path

    def test_known_overlaps_and_their_kind(self):
        import ncf_overlaps as O
        with tmpdir() as tmp:
            data = M.read_data(self.scene(tmp))
            out = io.StringIO()
            r = O.report(data, {1: D, 2: D}, top=5, out=out)
        self.assertEqual(len(r["overlap"]), 2)
        self.assertAlmostEqual(r["overlap"][0], D - 40 * UM, delta=1e-12)
        self.assertAlmostEqual(r["angle"][0], 30.0, delta=1e-6)
        self.assertTrue(r["free_end"][r["i"][0]] and r["free_end"][r["j"][0]])
        self.assertAlmostEqual(r["overlap"][1], 10 * UM, delta=1e-12)
        self.assertAlmostEqual(r["angle"][1], 90.0, delta=1e-6)
        self.assertFalse(r["free_end"][r["i"][1]] or r["free_end"][r["j"][1]])
        text = out.getvalue()
        self.assertIn("| both segments at a free chain end | 1 | 29.00 | 0.420 | 1 |", text)
        self.assertIn("| neither | 1 | 10.00 | 0.145 | 0 |", text)

    def test_thicker_chains_touch_at_the_mean_diameter(self):
        # layer 2 twice as thick: the crossing's contact distance is 1.5 d, overlap 10 um + d / 2
        import ncf_overlaps as O
        with tmpdir() as tmp:
            data = M.read_data(self.scene(tmp))
            r = O.overlaps(data, {1: D, 2: 2 * D})
        self.assertAlmostEqual(r["overlap"][0], 10 * UM + 0.5 * D, delta=1e-12)

    def test_bad_diameter_and_missing_layer_are_errors(self):
        import ncf_overlaps as O
        with tmpdir() as tmp:
            path = self.scene(tmp)
            err = io.StringIO()
            with redirect_stderr(err):
                self.assertEqual(O.main([path, "--diameter", "0"]), 2)
            self.assertIn("--diameter 0 m: must be between 1 um and 5 mm", err.getvalue())
            with self.assertRaisesRegex(M.MeasureError, r"layer\(s\) \[2\] have no chain diameter"):
                O.overlaps(M.read_data(path), {1: D})


class CommandLine(unittest.TestCase):
    def fabric(self, tmp, skip_node=False, layer_of_second=1):
        lx, ly = 4.4 * MM, 2.0 * MM
        n = int(round(ly / (D / 3)))
        chains = [x_chain((k + 0.5) * ly / n, lx) for k in range(n)]
        chains[3].layer = layer_of_second
        p = os.path.join(tmp, "f.data")
        write_data(p, (lx, ly, -1 * MM, 1 * MM), chains, 3, skip_node_section=skip_node)
        nd = os.path.join(tmp, "f.needles")
        write_needles(nd, [(1.1 * MM, 1.0 * MM)])
        card = os.path.join(tmp, "f.card")
        write_card(card, [0.0], [1.0])
        return p, nd, card

    def test_outputs(self):
        with tmpdir() as tmp:
            p, nd, card = self.fabric(tmp)
            out = os.path.join(tmp, "out")
            rc, so, se = run_cli([p, "--needles", nd, "--card", card, "--out", out, "-q"])
            self.assertEqual(rc, 0, se)
            for f in ("ncf-measure.md", "ncf-measure-summary.csv", "ncf-measure-defects.csv",
                      "ncf-measure-orientation.csv", "ncf-measure-orientation.png",
                      "f-layer1-map.png"):
                self.assertTrue(os.path.getsize(os.path.join(out, f)) > 0, f)
            with open(os.path.join(out, "ncf-measure-summary.csv")) as f:
                text = f.read()
            self.assertIn("stitching points without a visible crack,1,100", text)

    def expect_error(self, argv, *fragments):
        rc, so, se = run_cli(argv)
        self.assertEqual(rc, 1, se)
        self.assertIn("ncf-measure: ERROR:", se)
        self.assertNotIn("Traceback", se)
        for f in fragments:
            self.assertIn(f, se)

    def test_errors(self):
        with tmpdir() as tmp:
            p, nd, card = self.fabric(tmp, skip_node=True)
            self.expect_error([p, "--needles", nd, "--card", card, "--out", tmp], p, "no NCF_NODE section")
            p, nd, card = self.fabric(tmp, layer_of_second=5)
            self.expect_error([p, "--needles", nd, "--card", card, "--out", tmp], p + ":", "has layer 5")
            p, nd, card = self.fabric(tmp)
            empty = os.path.join(tmp, "empty.needles")
            with open(empty, "w") as f:
                f.write("# nothing\n")
            self.expect_error([p, "--needles", empty, "--card", card, "--out", tmp], empty,
                              "no stitching points")
            bad = os.path.join(tmp, "bad.needles")
            with open(bad, "w") as f:
                f.write("0.001 0.001\n0.002 zz\n")
            self.expect_error([p, "--needles", bad, "--card", card, "--out", tmp], bad + ":2", "'zz'")
            card2 = os.path.join(tmp, "two.card")
            write_card(card2, [0.0, 90.0])
            self.expect_error([p, "--needles", nd, "--card", card2, "--out", tmp], "layer 2 has no bonds")
            self.expect_error([p, "--needles", nd, "--card", card, "--layers", "7", "--out", tmp],
                              "unknown layer 7")
            self.expect_error([os.path.join(tmp, "missing.data"), "--needles", nd, "--card", card],
                              "missing.data")
            self.expect_error([p, "--needles", nd, "--card", card, "--resolution", "20um"],
                              "at most 10 um")
            far = os.path.join(tmp, "far.needles")
            write_needles(far, [(9 * MM, 1 * MM)])
            self.expect_error([p, "--needles", far, "--card", card, "--out", tmp], far, "outside the box")
            q = os.path.join(tmp, "atomic.data")
            write_data(q, (1 * MM, 1 * MM, 0, 1 * MM), [x_chain(0.5 * MM, 1 * MM)], 2,
                       style_comment="atomic")
            self.expect_error([q, "--needles", nd, "--card", card], q + ":", "atom_style bond")


if __name__ == "__main__":
    unittest.main(verbosity=2)
