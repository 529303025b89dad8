#!/usr/bin/python3
"""ncf-measure: measure a (generated or as-manufactured) non-crimp fabric as the paper's scans did.

Reads a LAMMPS data file (atom_style bond, with the NCF_NODE section), the stitching points
(PREFIX.needles) and the fabric's nominal angles (PREFIX.summary or the fabric card), and measures
per fibrous layer:

  - the orientation of every bond projected on the fabric plane, as a deviation from the layer's
    nominal angle, length-weighted (probability density, mean, SD);
  - the defects seen from the layer's face with the other layers and the yarn removed: a periodic
    coverage map (each segment's cylinder projected on the plane), the gaps as periodic connected
    uncovered regions, cracks at stitching points (length, width), covered stitching points,
    channel widths between stitching points;
  - the tilt of the stitching-yarn loops from the machine direction (x).

Definitions, outputs and limits: doc/ncf_measure.md. Only Debian's python3-numpy, python3-scipy and
python3-matplotlib are used.
"""

import argparse
import math
import os
import re
import sys

import numpy as np

__all__ = ["MeasureError", "Fabric", "LayerInfo", "Data", "read_data", "read_needles",
           "read_summary", "read_card", "Grid", "rasterize", "layer_orientation",
           "weighted_stats", "wrap_deviation", "analyse_gaps", "measure_layer",
           "loop_tilts", "main"]


class MeasureError(Exception):
    """Input the tool cannot measure; the message names the file, line/section and value."""


# ----------------------------------------------------------------------------- fabric description

class LayerInfo:
    def __init__(self, index, angle, sigma=0.0, d_c=69e-6):
        self.index = index          # 1 = bottom layer
        self.angle = angle          # nominal angle [deg] from +x towards +y
        self.sigma = sigma          # sampling SD [deg]
        self.d_c = d_c              # contact diameter of the chains [m]
        self.sampled_mean = None    # the generator's sampled chain angles (summary only)
        self.sampled_std = None


class Fabric:
    def __init__(self, source):
        self.source = source
        self.layers = []            # LayerInfo, bottom first
        self.loops = "bottom"       # face of the stitching loops
        self.yarn_d = None          # yarn chain diameter [m] (summary only)
        self.size = None            # RVE Lx, Ly [m] (summary only)
        self.points = None          # number of stitching points (summary only)

    def layer(self, index):
        for L in self.layers:
            if L.index == index:
                return L
        return None


_LENGTH = {"m": 1.0, "mm": 1e-3, "um": 1e-6, "micron": 1e-6}
_ANGLE = {"deg": 1.0, "rad": 180.0 / math.pi}


def _read_lines(path):
    try:
        with open(path, "r", encoding="utf-8", errors="replace") as f:
            return f.read().splitlines()
    except OSError as e:
        raise MeasureError("cannot read %s: %s" % (path, e.strerror or e))


def describe_error(e):
    """The words of an error that is not a MeasureError (a file that cannot be written, a value
    numpy refuses), for a message without a traceback."""
    if isinstance(e, OSError):
        name = e.filename if e.filename is not None else ""
        return "%s%s" % ("%s: " % name if name else "", e.strerror or e)
    return "%s: %s" % (type(e).__name__, e)


def join_negative_values(argv, options):
    """'--opt -1e-3' as '--opt=-1e-3': argparse takes a value that starts with '-' and is not a
    plain negative number (an exponent, a unit) for an option."""
    out, i = [], 0
    while i < len(argv):
        if argv[i] in options and i + 1 < len(argv) and re.match(r"^-[0-9.]", argv[i + 1]):
            out.append("%s=%s" % (argv[i], argv[i + 1]))
            i += 2
        else:
            out.append(argv[i])
            i += 1
    return out


def _length_text(text):
    """A length: a finite number with an optional unit m, mm, um, micron (metres without one)."""
    m = re.match(r"^\s*([-+0-9.eE]+)\s*(m|mm|um|micron)?\s*$", text)
    try:
        v = float(m.group(1)) if m else float("nan")
    except ValueError:
        v = float("nan")
    if not math.isfinite(v):
        raise ValueError("'%s' is not a finite length (a number with an optional unit m, mm, um)"
                         % text)
    return v * _LENGTH[m.group(2) or "m"]


def _num(text, where, what):
    try:
        v = float(text)
    except ValueError:
        raise MeasureError("%s: %s: value '%s' is not a number" % (where, what, text))
    if not math.isfinite(v):
        raise MeasureError("%s: %s: value '%s' is not finite" % (where, what, text))
    return v


def _with_unit(words, table, where, key):
    v = _num(words[0], where, "key '%s'" % key)
    if len(words) > 1:
        u = words[1]
        if u not in table:
            raise MeasureError("%s: key '%s': unknown unit '%s' (expected one of: %s)"
                               % (where, key, u, ", ".join(sorted(table))))
        v *= table[u]
    return v


def read_summary(path):
    """The generator's PREFIX.summary: layer angles, sigmas, d_c, sampled stats, loop face."""
    fab = Fabric(path)
    cur = None
    in_yarn = False
    for n, line in enumerate(_read_lines(path), 1):
        where = "%s:%d" % (path, n)
        s = line.strip()
        m = re.match(r"layer (\d+) \(atom/bond type \d+\)$", s)
        if m:
            cur = LayerInfo(int(m.group(1)), None)
            fab.layers.append(cur)
            in_yarn = False
            continue
        if s.startswith("stitching yarn"):
            cur, in_yarn = None, True
            continue
        m = re.match(r"size Lx \(machine\) x Ly \(gauge\)\s+(\S+) x (\S+) mm", s)
        if m:
            fab.size = (_num(m.group(1), where, "RVE Lx") * 1e-3, _num(m.group(2), where, "RVE Ly") * 1e-3)
        m = re.match(r"courses, needles \(stitching points\)\s+(\d+), (\d+)", s)
        if m:
            fab.points = int(m.group(2))
        if s == "checks":
            cur, in_yarn = None, False
            continue
        if cur is not None:
            m = re.match(r"nominal angle, sigma\s+(\S+) deg, (\S+) deg", s)
            if m:
                cur.angle = _num(m.group(1), where, "nominal angle")
                cur.sigma = _num(m.group(2), where, "sigma")
            m = re.match(r"chain d_c, packing\s+(\S+) (\S+),", s)
            if m:
                cur.d_c = _with_unit([m.group(1), m.group(2)], _LENGTH, where, "chain d_c")
            m = re.match(r"chain angles: mean, sample std\s+(\S+) deg, (\S+) deg", s)
            if m:
                cur.sampled_mean = _num(m.group(1), where, "chain angles mean")
                cur.sampled_std = _num(m.group(2), where, "chain angles sample std")
        elif in_yarn:
            m = re.match(r"chain diameter(?: \(hexagonal packing\)|, packing)\s+(\S+) ([^\s,]+)", s)
            if m:
                fab.yarn_d = _with_unit([m.group(1), m.group(2)], _LENGTH, where, "yarn diameter")
            m = re.match(r"loops on / underlaps on\s+(\w+) /", s)
            if m:
                fab.loops = m.group(1)
    if not fab.layers:
        raise MeasureError("%s: no 'layer N (atom/bond type N)' block: not an ncf-gen summary" % path)
    for L in fab.layers:
        if L.angle is None:
            raise MeasureError("%s: layer %d has no 'nominal angle, sigma' line" % (path, L.index))
    _check_layers(fab, path)
    return fab


def read_card(path):
    """A fabric card (doc/ncf-gen.md): layer angles and sigmas, chain_diameter, loops."""
    fab = Fabric(path)
    d_c = 69e-6
    cur = None
    for n, line in enumerate(_read_lines(path), 1):
        where = "%s:%d" % (path, n)
        words = line.split("#", 1)[0].split()
        if not words:
            continue
        key, vals = words[0], words[1:]
        if key == "layer":
            if not vals:
                raise MeasureError("%s: key 'layer': missing angle" % where)
            cur = LayerInfo(len(fab.layers) + 1, _with_unit(vals, _ANGLE, where, key))
            fab.layers.append(cur)
        elif key == "sigma":
            if cur is None:
                raise MeasureError("%s: key 'sigma' outside a layer block" % where)
            if not vals:
                raise MeasureError("%s: key 'sigma': missing value" % where)
            cur.sigma = _with_unit(vals, _ANGLE, where, key)
        elif key == "chain_diameter":
            if not vals:
                raise MeasureError("%s: key 'chain_diameter': missing value" % where)
            d_c = _with_unit(vals, _LENGTH, where, key)
            if d_c <= 0:
                raise MeasureError("%s: key 'chain_diameter': value '%s' must be > 0"
                                   % (where, vals[0]))
        elif key == "loops":
            if not vals or vals[0] not in ("bottom", "top"):
                raise MeasureError("%s: key 'loops': value '%s' must be bottom or top"
                                   % (where, " ".join(vals)))
            fab.loops = vals[0]
    if not fab.layers:
        raise MeasureError("%s: no 'layer' line: not a fabric card" % path)
    for L in fab.layers:
        L.d_c = d_c
    _check_layers(fab, path)
    return fab


def _check_layers(fab, path):
    for L in fab.layers:
        if not (L.d_c > 0):
            raise MeasureError("%s: layer %d: chain diameter %g must be > 0" % (path, L.index, L.d_c))
        if L.sigma < 0:
            raise MeasureError("%s: layer %d: sigma %g must be >= 0" % (path, L.index, L.sigma))


def read_needles(path):
    """PREFIX.needles: 'x y' per line, '#' comments. Returns an (n, 2) array."""
    pts = []
    for n, line in enumerate(_read_lines(path), 1):
        s = line.split("#", 1)[0].split()
        if not s:
            continue
        if len(s) != 2:
            raise MeasureError("%s:%d: stitching point '%s': expected 'x y'" % (path, n, line.strip()))
        pts.append((_num(s[0], "%s:%d" % (path, n), "x"), _num(s[1], "%s:%d" % (path, n), "y")))
    if not pts:
        raise MeasureError("%s: no stitching points (expected lines 'x y')" % path)
    return np.array(pts, dtype=float)


# ----------------------------------------------------------------------------- LAMMPS data file

class Data:
    """Atoms (wrapped positions), bonds (index pairs) and NCF_NODE of one data file."""

    def __init__(self, path):
        self.path = path
        self.lo = np.zeros(3)
        self.hi = np.ones(3)
        self.ids = None
        self.mol = None
        self.type = None
        self.pos = None
        self.layer = None
        self.end = None
        self.bonds = None         # (M, 2) indices into the atom arrays
        self.bond_type = None

    @property
    def lx(self):
        return self.hi[0] - self.lo[0]

    @property
    def ly(self):
        return self.hi[1] - self.lo[1]

    def min_image(self, d):
        """Minimum image in x and y of (..., 2 or 3) vectors (z is not periodic)."""
        d = np.array(d, dtype=float, copy=True)
        d[..., 0] -= self.lx * np.round(d[..., 0] / self.lx)
        d[..., 1] -= self.ly * np.round(d[..., 1] / self.ly)
        return d

    def append(self, other):
        """Append another data file's atoms and bonds (e.g. the generator's yarn.data)."""
        if not (np.allclose(self.lo[:2], other.lo[:2]) and np.allclose(self.hi[:2], other.hi[:2])):
            raise MeasureError("%s: box x/y %s..%s differs from %s's %s..%s"
                               % (other.path, other.lo[:2], other.hi[:2], self.path,
                                  self.lo[:2], self.hi[:2]))
        off = len(self.ids)
        idoff = int(self.ids.max()) if len(self.ids) else 0
        self.ids = np.concatenate([self.ids, other.ids + idoff])
        moloff = int(self.mol.max()) if len(self.mol) else 0
        self.mol = np.concatenate([self.mol, other.mol + moloff])
        self.type = np.concatenate([self.type, other.type])
        self.pos = np.concatenate([self.pos, other.pos])
        # (a file read without its NCF_NODE section has no layers: neither has the whole then)
        both = self.layer is not None and other.layer is not None
        self.layer = np.concatenate([self.layer, other.layer]) if both else None
        self.end = np.concatenate([self.end, other.end]) if both else None
        self.bonds = np.concatenate([self.bonds, other.bonds + off])
        self.bond_type = np.concatenate([self.bond_type, other.bond_type])
        self.lo[2] = min(self.lo[2], other.lo[2])
        self.hi[2] = max(self.hi[2], other.hi[2])


def _is_number(tok):
    try:
        float(tok)
        return True
    except ValueError:
        return False


def read_data(path, need_nodes=True):
    """A LAMMPS data file of atom_style bond or angle with the NCF_NODE section (write_data or
    ncf-gen). need_nodes=False: a file without NCF_NODE is read too (layer and end None); the
    reader of ncf-export."""
    lines = _read_lines(path)
    d = Data(path)
    nat = None
    # header
    i = 1
    while i < len(lines):
        s = lines[i].split("#", 1)[0].split()
        if s and not _is_number(s[0]):
            break
        if s:
            where = "%s:%d" % (path, i + 1)
            if s[-1] == "atoms" and len(s) == 2:
                nat = int(_num(s[0], where, "atoms"))
            for k, ax in (("xlo", 0), ("ylo", 1), ("zlo", 2)):
                if len(s) == 4 and s[2] == k:
                    d.lo[ax] = _num(s[0], where, k)
                    d.hi[ax] = _num(s[1], where, k.replace("lo", "hi"))
            if len(s) == 6 and s[3:] == ["xy", "xz", "yz"]:
                tilt = [_num(t, where, "tilt") for t in s[:3]]
                if any(t != 0.0 for t in tilt):
                    raise MeasureError("%s: triclinic box (xy xz yz = %s): only orthogonal boxes "
                                       "can be measured" % (where, " ".join(s[:3])))
        i += 1
    if nat is None:
        raise MeasureError("%s: no 'N atoms' line in the header: not a LAMMPS data file" % path)
    if d.lx <= 0 or d.ly <= 0:
        raise MeasureError("%s: box x or y has no extent (xlo xhi / ylo yhi lines)" % path)
    # sections: a title line (first word not a number), then numeric lines up to the next title
    sections = {}
    title, title_line, rows = None, 0, []
    while i <= len(lines):
        raw = lines[i] if i < len(lines) else None
        body = raw.split("#", 1)[0].split() if raw is not None else None
        if raw is None or (body and not _is_number(body[0])):
            if title is not None:
                sections[title] = (title_line, rows, comment)
            if raw is None:
                break
            title, title_line, rows = " ".join(body), i + 1, []
            comment = raw.split("#", 1)[1].strip() if "#" in raw else ""
        elif body:
            rows.append((i + 1, body))
        i += 1

    def need(name):
        if name not in sections:
            extra = ""
            if name == "NCF_NODE":
                extra = (" (the per-atom layer index; write it with 'fix NCF_NODE all property/atom "
                         "i_ncf_layer i_ncf_end' defined before write_data)")
            raise MeasureError("%s: no %s section%s" % (path, name, extra))
        return sections[name]

    tl, rows, comment = need("Atoms")
    # atom_style angle (the stage scripts' style, the layers of 'bending bundle') has the
    # columns of atom_style bond; its Angles section is not needed here
    if comment and comment.split()[0] not in ("bond", "angle"):
        raise MeasureError("%s:%d: section 'Atoms # %s': only atom_style bond or angle can be read"
                           % (path, tl, comment))
    if len(rows) != nat:
        raise MeasureError("%s:%d: section Atoms has %d lines, the header says %d atoms"
                           % (path, tl, len(rows), nat))
    arr = np.zeros((nat, 6))
    img = np.zeros((nat, 3))
    for k, (ln, w) in enumerate(rows):
        if len(w) not in (6, 9):
            raise MeasureError("%s:%d: section Atoms: '%s': expected 'id mol type x y z [ix iy iz]' "
                               "(atom_style bond)" % (path, ln, " ".join(w)))
        try:
            arr[k] = [float(t) for t in w[:6]]
            if len(w) == 9:
                img[k] = [float(t) for t in w[6:]]
        except ValueError:
            raise MeasureError("%s:%d: section Atoms: '%s' is not numeric" % (path, ln, " ".join(w)))
    d.ids = arr[:, 0].astype(np.int64)
    d.mol = arr[:, 1].astype(np.int64)
    d.type = arr[:, 2].astype(np.int64)
    d.pos = arr[:, 3:6].copy()
    # wrap into the box (x, y periodic)
    for ax in (0, 1):
        L = d.hi[ax] - d.lo[ax]
        d.pos[:, ax] = d.lo[ax] + np.mod(d.pos[:, ax] - d.lo[ax], L)
    order = np.argsort(d.ids)
    sorted_ids = d.ids[order]
    if len(sorted_ids) > 1 and np.any(sorted_ids[1:] == sorted_ids[:-1]):
        dup = sorted_ids[1:][sorted_ids[1:] == sorted_ids[:-1]][0]
        raise MeasureError("%s: section Atoms: atom id %d appears twice" % (path, dup))

    def index_of(tags, section, lns):
        pos = np.searchsorted(sorted_ids, tags)
        pos = np.clip(pos, 0, len(sorted_ids) - 1)
        bad = sorted_ids[pos] != tags
        if np.any(bad):
            k = int(np.nonzero(bad)[0][0])
            raise MeasureError("%s:%d: section %s: atom id %d is not in the Atoms section"
                               % (path, lns[k], section, tags[k]))
        return order[pos]

    # bonds
    if "Bonds" in sections:
        tl, rows, _ = sections["Bonds"]
        b = np.zeros((len(rows), 4), dtype=np.int64)
        for k, (ln, w) in enumerate(rows):
            if len(w) < 4:
                raise MeasureError("%s:%d: section Bonds: '%s': expected 'id type atom1 atom2'"
                                   % (path, ln, " ".join(w)))
            try:
                b[k] = [int(t) for t in w[:4]]
            except ValueError:
                raise MeasureError("%s:%d: section Bonds: '%s' is not integer"
                                   % (path, ln, " ".join(w)))
        lns = [ln for ln, _ in rows]
        d.bonds = np.stack([index_of(b[:, 2], "Bonds", lns), index_of(b[:, 3], "Bonds", lns)], 1) \
            if len(rows) else np.zeros((0, 2), dtype=np.int64)
        d.bond_type = b[:, 1]
    else:
        d.bonds = np.zeros((0, 2), dtype=np.int64)
        d.bond_type = np.zeros(0, dtype=np.int64)
    # NCF_NODE
    if not need_nodes and "NCF_NODE" not in sections:
        return d
    tl, rows, _ = need("NCF_NODE")
    if len(rows) != nat:
        raise MeasureError("%s:%d: section NCF_NODE has %d lines, the file has %d atoms"
                           % (path, tl, len(rows), nat))
    nn = np.zeros((nat, 3), dtype=np.int64)
    for k, (ln, w) in enumerate(rows):
        if len(w) != 3:
            raise MeasureError("%s:%d: section NCF_NODE: '%s': expected 'id layer end'"
                               % (path, ln, " ".join(w)))
        try:
            nn[k] = [int(t) for t in w]
        except ValueError:
            raise MeasureError("%s:%d: section NCF_NODE: '%s' is not integer" % (path, ln, " ".join(w)))
    idx = index_of(nn[:, 0], "NCF_NODE", [ln for ln, _ in rows])
    d.layer = np.zeros(nat, dtype=np.int64)
    d.end = np.zeros(nat, dtype=np.int64)
    d.layer[idx] = nn[:, 1]
    d.end[idx] = nn[:, 2]
    d.node_line = np.zeros(nat, dtype=np.int64)
    d.node_line[idx] = [ln for ln, _ in rows]
    return d


def check_box(data, fab, path):
    """The summary's RVE size is the data file's box in x and y (to 1e-6 of it: the stages keep
    the box); also for ncf-export."""
    if fab.size is not None:
        lx, ly = data.hi[0] - data.lo[0], data.hi[1] - data.lo[1]
        if abs(lx - fab.size[0]) > 1e-6 * fab.size[0] + 1e-7 or \
                abs(ly - fab.size[1]) > 1e-6 * fab.size[1] + 1e-7:
            raise MeasureError("%s: box %g x %g mm, but %s describes an RVE of %g x %g mm: the "
                               "summary of another fabric?" % (path, lx * 1e3, ly * 1e3, fab.source,
                                                                fab.size[0] * 1e3, fab.size[1] * 1e3))


def check_fabric(data, fab, path, needles, needles_path):
    """The summary, the needles and the data file are of one fabric: the summary's RVE size is the
    data file's box in x and y (to 1e-6 of it: the stages keep the box), the needle file holds
    the summary's number of stitching points, none twice."""
    check_box(data, fab, path)
    if fab.points is not None and len(needles) != fab.points:
        raise MeasureError("%s: %d stitching points, but %s describes %d: the needles of another "
                           "fabric?" % (needles_path, len(needles), fab.source, fab.points))
    if len(needles) > 1:
        key = np.round(np.asarray(needles) / 1e-9).astype(np.int64)
        _, first, count = np.unique(key, axis=0, return_index=True, return_counts=True)
        if np.any(count > 1):
            q = needles[first[np.nonzero(count > 1)[0][0]]]
            raise MeasureError("%s: stitching point (%g, %g) is listed twice" % (needles_path, q[0], q[1]))


def check_layers(data, fab):
    """Every node's layer must be 0 (yarn) or one of the fabric's layers."""
    known = set(L.index for L in fab.layers)
    bad = ~np.isin(data.layer, list(known | {0}))
    if np.any(bad):
        k = int(np.nonzero(bad)[0][0])
        raise MeasureError("%s:%d: section NCF_NODE: atom %d has layer %d, but %s has layers %s "
                           "(0 = stitching yarn)"
                           % (data.path, data.node_line[k], data.ids[k], data.layer[k], fab.source,
                              ", ".join(str(i) for i in sorted(known))))


# ----------------------------------------------------------------------------- orientation

def wrap_deviation(a):
    """Angles as axes: wrap to (-90, 90]."""
    return 90.0 - np.mod(90.0 - np.asarray(a, dtype=float), 180.0)


def layer_bonds(data, layer):
    """Indices of the bonds whose two nodes belong to the layer."""
    la = data.layer[data.bonds[:, 0]]
    lb = data.layer[data.bonds[:, 1]]
    return np.nonzero((la == layer) & (lb == layer))[0]


def bond_deviation(data, pairs, angle):
    """In-plane deviation [deg] from the nominal angle and projected length of node pairs."""
    v = data.min_image(data.pos[pairs[:, 1], :2] - data.pos[pairs[:, 0], :2])
    w = np.hypot(v[:, 0], v[:, 1])
    phi = np.degrees(np.arctan2(v[:, 1], v[:, 0]))
    return wrap_deviation(phi - angle), w


def layer_orientation(data, layer, angle):
    b = layer_bonds(data, layer)
    return bond_deviation(data, data.bonds[b], angle)


def chain_angles(data, layer, angle):
    """Per chain (molecule ID) of the layer: the length-weighted mean deviation of its bonds, i.e.
    the angle of a straight chain. Returns the per-chain deviations [deg]."""
    b = layer_bonds(data, layer)
    dev, w = bond_deviation(data, data.bonds[b], angle)
    mol = data.mol[data.bonds[b, 0]]
    ids, inv = np.unique(mol, return_inverse=True)
    W = np.bincount(inv, weights=w, minlength=len(ids))
    S = np.bincount(inv, weights=w * dev, minlength=len(ids))
    return S[W > 0] / W[W > 0]


def weighted_stats(x, w):
    W = np.sum(w)
    if not W > 0:
        return float("nan"), float("nan")
    m = np.sum(w * x) / W
    return float(m), float(math.sqrt(max(0.0, np.sum(w * (x - m) ** 2) / W)))


def density(x, w, bins, rng):
    edges = np.linspace(-rng, rng, bins + 1)
    h, _ = np.histogram(x, bins=edges, weights=w)
    W = np.sum(w)
    return edges, (h / (W * (edges[1] - edges[0])) if W > 0 else h * 0.0)


# ----------------------------------------------------------------------------- coverage map

class Grid:
    """Pixels tiling the periodic box exactly: nx = ceil(Lx / h), pixel (j, i) centre
    (xlo + (i + 1/2) hx, ylo + (j + 1/2) hy)."""

    def __init__(self, xlo, ylo, lx, ly, h):
        if not (h > 0):
            raise MeasureError("resolution %g must be > 0" % h)
        self.xlo, self.ylo, self.lx, self.ly = xlo, ylo, lx, ly
        self.nx = max(1, int(math.ceil(lx / h - 1e-9)))
        self.ny = max(1, int(math.ceil(ly / h - 1e-9)))
        if self.nx * self.ny > 60e6:
            raise MeasureError("the map would have %d x %d pixels at resolution %g m: use a coarser "
                               "--resolution" % (self.nx, self.ny, h))
        self.hx = lx / self.nx
        self.hy = ly / self.ny

    @classmethod
    def of(cls, data, h):
        return cls(data.lo[0], data.lo[1], data.lx, data.ly, h)

    def centres(self):
        x = self.xlo + (np.arange(self.nx) + 0.5) * self.hx
        y = self.ylo + (np.arange(self.ny) + 0.5) * self.hy
        return x, y


def rasterize(grid, a, b, r, za=None, zb=None, value=None, top=True, chunk_pixels=3_000_000):
    """Coverage of capsules (segments a-b, radius r) on the periodic grid: a pixel is covered when
    its centre is within r of a segment. a, b: (S, 2), b unwrapped relative to a (minimum image).
    With za, zb, value: also the value of the segment seen first from the top (largest z at the
    closest point; top=False: smallest z). Returns covered (ny, nx) bool [, value map]."""
    a = np.asarray(a, float).reshape(-1, 2)
    b = np.asarray(b, float).reshape(-1, 2)
    S = len(a)
    r = np.broadcast_to(np.asarray(r, float), (S,))
    nx, ny, hx, hy = grid.nx, grid.ny, grid.hx, grid.hy
    cov = np.zeros(nx * ny, dtype=bool)
    want = value is not None
    if want:
        best = np.full(nx * ny, -np.inf)
        vmap = np.full(nx * ny, np.nan)
        sgn = 1.0 if top else -1.0
    if S == 0:
        return (cov.reshape(ny, nx), vmap.reshape(ny, nx)) if want else cov.reshape(ny, nx)
    ax = a[:, 0] - grid.xlo
    ay = a[:, 1] - grid.ylo
    bx = b[:, 0] - grid.xlo
    by = b[:, 1] - grid.ylo
    i0 = np.ceil((np.minimum(ax, bx) - r) / hx - 0.5).astype(np.int64)
    i1 = np.floor((np.maximum(ax, bx) + r) / hx - 0.5).astype(np.int64)
    j0 = np.ceil((np.minimum(ay, by) - r) / hy - 0.5).astype(np.int64)
    j1 = np.floor((np.maximum(ay, by) + r) / hy - 0.5).astype(np.int64)
    kx = np.maximum(i1 - i0 + 1, 0)
    ky = np.maximum(j1 - j0 + 1, 0)
    order = np.argsort(kx * ky, kind="stable")
    start = 0
    while start < S:
        # a chunk of segments with similar box sizes
        kmax = int(kx[order[start]] * ky[order[start]])
        stop = start + 1
        while stop < S:
            kk = int(kx[order[stop]]) * int(ky[order[stop]])
            if (stop - start + 1) * max(kk, kmax, 1) > chunk_pixels:
                break
            kmax = max(kmax, kk)
            stop += 1
        sel = order[start:stop]
        start = stop
        KX = int(kx[sel].max())
        KY = int(ky[sel].max())
        if KX == 0 or KY == 0:
            continue
        I = i0[sel, None, None] + np.arange(KX)[None, None, :]
        J = j0[sel, None, None] + np.arange(KY)[None, :, None]
        cx = (I + 0.5) * hx
        cy = (J + 0.5) * hy
        sax, say = ax[sel, None, None], ay[sel, None, None]
        ex, ey = bx[sel, None, None] - sax, by[sel, None, None] - say
        ee = ex * ex + ey * ey
        with np.errstate(invalid="ignore", divide="ignore"):
            t = ((cx - sax) * ex + (cy - say) * ey) / ee
        t = np.where(ee > 0, np.clip(t, 0.0, 1.0), 0.0)
        dx = cx - sax - t * ex
        dy = cy - say - t * ey
        rr = r[sel, None, None]
        inside = (dx * dx + dy * dy <= rr * rr) & (I <= i1[sel, None, None]) & \
            (J <= j1[sel, None, None])
        flat = (np.mod(J, ny) * nx + np.mod(I, nx))
        f = np.broadcast_to(flat, inside.shape)[inside]
        cov[f] = True
        if want:
            zz = sgn * (za[sel, None, None] + t * (zb[sel, None, None] - za[sel, None, None]))
            zk = np.broadcast_to(zz, inside.shape)[inside]
            vk = np.broadcast_to(value[sel, None, None], inside.shape)[inside]
            o = np.lexsort((zk, f))
            f, zk, vk = f[o], zk[o], vk[o]
            last = np.ones(len(f), dtype=bool)
            last[:-1] = f[1:] != f[:-1]
            f, zk, vk = f[last], zk[last], vk[last]
            up = zk > best[f]
            best[f[up]] = zk[up]
            vmap[f[up]] = vk[up]
    if want:
        return cov.reshape(ny, nx), vmap.reshape(ny, nx)
    return cov.reshape(ny, nx)


def layer_segments(data, layer):
    """Segments of the layer's chains: its bonds, plus half an element beyond every chain end on
    a main face (NCF_NODE end code 1-4) along its last bond. A chain ends half an element inside
    its main face and the chain that continues it (averaged PBC, no bond) starts half an element
    inside the opposite face; the two extensions meet at the face, so the faces do not read as
    gaps. Returns (start points (S, 3), vectors (S, 3), is_bond (S,))."""
    b = data.bonds[layer_bonds(data, layer)]
    a = data.pos[b[:, 0]]
    v = data.min_image(data.pos[b[:, 1]] - a)
    nb = np.full(len(data.layer), -1, dtype=np.int64)      # a bonded neighbour of each node
    nb[b[:, 0]] = b[:, 1]
    nb[b[:, 1]] = b[:, 0]
    ends = np.nonzero((data.layer == layer) & (data.end > 0) & (nb >= 0))[0]
    ea = data.pos[ends]
    ev = 0.5 * data.min_image(data.pos[ends] - data.pos[nb[ends]])
    return (np.concatenate([a, ea]), np.concatenate([v, ev]),
            np.concatenate([np.ones(len(a), bool), np.zeros(len(ea), bool)]))


def coverage(data, grid, layer, angle, d_c, top=True):
    """Coverage map and deviation map (seen from the top or the bottom) of one layer."""
    a, v, _ = layer_segments(data, layer)
    dev = wrap_deviation(np.degrees(np.arctan2(v[:, 1], v[:, 0])) - angle)
    return rasterize(grid, a[:, :2], a[:, :2] + v[:, :2], 0.5 * d_c, a[:, 2], a[:, 2] + v[:, 2],
                     dev, top=top)


# ----------------------------------------------------------------------------- gaps

def label_periodic(gap):
    """Connected components (8-neighbour) of a periodic boolean map. Returns
    (label map, list of components); each component: dict(pixels=(j, i) arrays, shift=(sx, sy)
    integer box shifts per pixel that unwrap it, wraps=(bool x, bool y))."""
    from scipy import ndimage
    ny, nx = gap.shape
    lab, n = ndimage.label(gap, structure=np.ones((3, 3), dtype=int))
    # edges between pieces across the periodic faces: (piece a, piece b, shift of b relative to a)
    edges = []
    if nx > 1 or ny > 1:
        rows = np.arange(ny)
        for dj in (-1, 0, 1):
            jb = rows + dj
            sy = np.where(jb >= ny, 1, np.where(jb < 0, -1, 0))
            la = lab[rows, nx - 1]
            lb = lab[np.mod(jb, ny), 0]
            m = (la > 0) & (lb > 0)
            edges += [(int(p), int(q), 1, int(s)) for p, q, s in zip(la[m], lb[m], sy[m])]
        cols = np.arange(nx)
        for di in (-1, 0, 1):
            ib = cols + di
            sx = np.where(ib >= nx, 1, np.where(ib < 0, -1, 0))
            la = lab[ny - 1, cols]
            lb = lab[0, np.mod(ib, nx)]
            m = (la > 0) & (lb > 0)
            edges += [(int(p), int(q), int(s), 1) for p, q, s in zip(la[m], lb[m], sx[m])]
    edges = sorted(set(edges))
    adj = {}
    for p, q, sx, sy in edges:
        adj.setdefault(p, []).append((q, sx, sy))
        adj.setdefault(q, []).append((p, -sx, -sy))
    comp_of = np.zeros(n + 1, dtype=np.int64)
    shift = np.zeros((n + 1, 2), dtype=np.int64)
    comps = []
    for p0 in range(1, n + 1):
        if comp_of[p0]:
            continue
        c = len(comps) + 1
        comp_of[p0] = c
        members = [p0]
        wraps = [False, False]
        stack = [p0]
        while stack:
            p = stack.pop()
            for q, sx, sy in adj.get(p, ()):
                want = shift[p] + (sx, sy)
                if comp_of[q] == 0:
                    comp_of[q] = c
                    shift[q] = want
                    members.append(q)
                    stack.append(q)
                else:
                    dsh = want - shift[q]
                    if dsh[0]:
                        wraps[0] = True
                    if dsh[1]:
                        wraps[1] = True
        comps.append(dict(pieces=members, wraps=tuple(wraps)))
    # pixels per component
    jj, ii = np.nonzero(lab)
    pl = lab[jj, ii]
    o = np.argsort(comp_of[pl], kind="stable")
    jj, ii, pl = jj[o], ii[o], pl[o]
    cl = comp_of[pl]
    bounds = np.searchsorted(cl, np.arange(1, len(comps) + 2))
    clab = np.zeros_like(lab)
    clab[jj, ii] = cl
    for c, comp in enumerate(comps):
        s, e = bounds[c], bounds[c + 1]
        comp["j"] = jj[s:e]
        comp["i"] = ii[s:e]
        comp["sx"] = shift[pl[s:e], 0]
        comp["sy"] = shift[pl[s:e], 1]
    return clab, comps


def comp_xy(grid, comp):
    """Unwrapped pixel centres of a component."""
    x = grid.xlo + (comp["i"] + 0.5) * grid.hx + comp["sx"] * grid.lx
    y = grid.ylo + (comp["j"] + 0.5) * grid.hy + comp["sy"] * grid.ly
    return x, y


def extent(grid, x, y, angle):
    """Length along the direction `angle` and width across it of a set of pixel centres:
    length = span of s = p.u plus one pixel; width = the largest span of t = p.v among the
    stations (strips one pixel wide across u) plus one pixel."""
    h = math.sqrt(grid.hx * grid.hy)
    c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    su = x * c + y * s
    tv = -x * s + y * c
    length = float(su.max() - su.min() + h)
    k = np.floor((su - su.min()) / h).astype(np.int64)
    o = np.argsort(k, kind="stable")
    k, t = k[o], tv[o]
    starts = np.nonzero(np.r_[True, k[1:] != k[:-1]])[0]
    span = np.maximum.reduceat(t, starts) - np.minimum.reduceat(t, starts)
    return length, float(span.max() + h)


def _periodic_delta(grid, dx, dy):
    return dx - grid.lx * np.round(dx / grid.lx), dy - grid.ly * np.round(dy / grid.ly)


def channel_vector(needles, grid, angle, tol_deg=0.5):
    """The shortest lattice vector between stitching points (periodic images included) parallel
    to the layer direction (within tol_deg) and at most twice as long as the shortest distance
    between two stitching points, or None: the layer runs from stitching point to stitching
    point, so a channel can form between them."""
    c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    vecs = []
    p = needles[0]      # the lattice is the same from every stitching point
    for q in needles:
        for ix in range(-3, 4):
            for iy in range(-3, 4):
                v = np.array([q[0] + ix * grid.lx - p[0], q[1] + iy * grid.ly - p[1]])
                if math.hypot(*v) > 1e-9:
                    vecs.append(v)
    if not vecs:
        return None
    lens = [math.hypot(*v) for v in vecs]
    dnn = min(lens)
    best = None
    for v, L in zip(vecs, lens):
        along = v[0] * c + v[1] * s
        across = -v[0] * s + v[1] * c
        if L <= 2.0 * dnn + 1e-12 and abs(across) <= L * math.sin(math.radians(tol_deg)):
            if best is None or L < best[0] - 1e-12:
                best = (L, v * (1 if along > 0 else -1))
    return None if best is None else best[1]


def runs_across(grid, open_map, p, direction, search, reach=3e-3):
    """Open runs on the line through p along `direction` (unit vector), sampled every half pixel
    over +-(search + reach): the runs that overlap [-search, +search] count whole. Returns
    (total length of those runs, centre of their span relative to p) or (0, None)."""
    h = 0.5 * min(grid.hx, grid.hy)
    n = int(math.ceil((search + reach) / h))
    t = np.arange(-n, n + 1) * h
    x = p[0] + t * direction[0]
    y = p[1] + t * direction[1]
    i = np.mod(np.floor((x - grid.xlo) / grid.hx).astype(np.int64), grid.nx)
    j = np.mod(np.floor((y - grid.ylo) / grid.hy).astype(np.int64), grid.ny)
    o = open_map[j, i]
    d = np.diff(np.r_[0, o.astype(np.int8), 0])
    starts = np.nonzero(d == 1)[0]
    stops = np.nonzero(d == -1)[0]      # exclusive
    keep = (t[starts] <= search) & (t[stops - 1] >= -search)
    if not keep.any():
        return 0.0, None
    starts, stops = starts[keep], stops[keep]
    return (float(np.sum(stops - starts) * h),
            float(0.5 * (t[starts].min() + t[stops - 1].max())))


def analyse_gaps(grid, covered, needles, angle, capture, min_area=0.0, channel_search=0.3e-3):
    """Gaps of one layer's coverage map, assigned to stitching points and channels.

    Returns dict with: comps (list of component dicts with kind crack/channel/gap, needle,
    length, width, area), points (per stitching point: crack length/width or covered/channel),
    channels (per channel segment: midpoint, width), channel_vector."""
    gap = ~covered
    clab, comps = label_periodic(gap)
    area_px = grid.hx * grid.hy
    for c in comps:
        c["area"] = len(c["i"]) * area_px
        c["big"] = c["area"] >= min_area
    # components within the capture radius of each stitching point
    r_i = int(math.ceil(capture / grid.hx)) + 1
    r_j = int(math.ceil(capture / grid.hy)) + 1
    touch = []          # per needle: set of component numbers (1-based)
    for p in needles:
        pi = (p[0] - grid.xlo) / grid.hx - 0.5
        pj = (p[1] - grid.ylo) / grid.hy - 0.5
        I = np.arange(int(math.floor(pi)) - r_i, int(math.ceil(pi)) + r_i + 1)
        J = np.arange(int(math.floor(pj)) - r_j, int(math.ceil(pj)) + r_j + 1)
        dx = (I - pi) * grid.hx
        dy = (J - pj) * grid.hy
        m = dy[:, None] ** 2 + dx[None, :] ** 2 <= capture ** 2
        labs = clab[np.mod(J, grid.ny)[:, None], np.mod(I, grid.nx)[None, :]][m]
        touch.append(set(int(v) for v in np.unique(labs) if v > 0 and comps[v - 1]["big"]))
    ntouch = {}
    for k, s in enumerate(touch):
        for c in s:
            ntouch.setdefault(c, []).append(k)
    cv = channel_vector(needles, grid, angle)
    c_, s_ = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    for n, comp in enumerate(comps, 1):
        comp["needle"] = None
        if not comp["big"]:
            comp["kind"] = "small"
            continue
        ks = ntouch.get(n, [])
        if comp["wraps"][0] or comp["wraps"][1] or len(ks) >= 2:
            comp["kind"] = "channel"
        elif len(ks) == 1:
            comp["kind"] = "crack"
            comp["needle"] = ks[0]
        else:
            # assigned to the nearest stitching point, or to the channel line if that is nearer
            # and within the channel search distance of it
            x, y = comp_xy(grid, comp)
            if len(x) > 20000:
                sel = np.linspace(0, len(x) - 1, 20000).astype(np.int64)
                x, y = x[sel], y[sel]
            dP = []
            dC = []
            for p in needles:
                dx, dy = _periodic_delta(grid, x - p[0], y - p[1])
                dP.append(np.min(np.hypot(dx, dy)))
                if cv is not None:
                    along = dx * c_ + dy * s_
                    across = np.abs(-dx * s_ + dy * c_)
                    L = math.hypot(*cv)
                    inside = (along > 0) & (along < L)
                    dC.append(np.min(across[inside]) if inside.any() else np.inf)
            k = int(np.argmin(dP))
            comp["needle"] = k
            near_line = bool(dC) and min(dC) < dP[k] and min(dC) <= channel_search
            comp["kind"] = "channel" if near_line else "gap"
        x, y = comp_xy(grid, comp)
        if comp["wraps"][0] or comp["wraps"][1]:
            comp["length"], comp["width"] = float("inf"), float("nan")
        else:
            comp["length"], comp["width"] = extent(grid, x, y, angle)
    # per stitching point: the crack = union of the cracks touching it
    points = []
    for k, p in enumerate(needles):
        cracks = [c for c in touch[k] if comps[c - 1]["kind"] == "crack"]
        chans = [c for c in touch[k] if comps[c - 1]["kind"] == "channel"]
        rec = dict(index=k, x=float(p[0]), y=float(p[1]))
        if cracks:
            xs, ys = [], []
            for c in cracks:
                x, y = comp_xy(grid, comps[c - 1])
                # the image of the component nearest to this stitching point
                j = np.argmin(np.hypot(*_periodic_delta(grid, x - p[0], y - p[1])))
                dx, dy = _periodic_delta(grid, x[j] - p[0], y[j] - p[1])
                xs.append(x + (p[0] + dx - x[j]))
                ys.append(y + (p[1] + dy - y[j]))
            L, W = extent(grid, np.concatenate(xs), np.concatenate(ys), angle)
            rec.update(kind="crack", length=L, width=W,
                       area=sum(comps[c - 1]["area"] for c in cracks), comps=cracks)
        elif chans:
            rec.update(kind="channel", comps=chans)
        else:
            rec.update(kind="covered", comps=[])
        points.append(rec)
    # channel widths in the middle between consecutive stitching points
    channels = []
    if cv is not None:
        u = cv / math.hypot(*cv)
        v = np.array([-u[1], u[0]])
        is_channel = np.array([False] + [c["kind"] == "channel" for c in comps])
        open_map = is_channel[clab]             # only gaps that are channels open a channel
        for k, p in enumerate(needles):
            m = p + 0.5 * cv
            m = np.array([grid.xlo + (m[0] - grid.xlo) % grid.lx,
                          grid.ylo + (m[1] - grid.ylo) % grid.ly])
            w, off = runs_across(grid, open_map, m, v, channel_search)
            channels.append(dict(index=k, x=float(m[0]), y=float(m[1]), width=w,
                                 offset=off))
    return dict(comps=comps, clab=clab, points=points, channels=channels, channel_vector=cv)


# ----------------------------------------------------------------------------- loops

def loop_tilts(data, fab, loop_z=None, min_length=0.2e-3):
    """Loops of the stitching yarn on the loop face and their tilt from x.

    A loop is a connected run of yarn bonds whose two nodes both lie beyond loop_z on the loop
    face (default: the middle of the outermost layer there, the median z of its nodes). Its tilt
    is the angle from +x of its long axis, in (-90, 90]: the principal direction of the
    length-weighted orientation tensor of its in-plane segments. That is the direction of its
    sides for a knitted loop (both ends out of one hole, out and back with a head across:
    exactly, whether or not its two legs sit side by side along the axis), and of the loop itself
    for a running stitch's loop from one hole to the next. x, y: the midpoint of its ends (the
    hole of a knitted loop); chord: its extent along the axis (loops shorter than min_length are
    not counted)."""
    yarn = data.layer == 0
    if not yarn.any():
        return None, []
    bottom = fab.loops == "bottom"
    if loop_z is None:
        outer = min(L.index for L in fab.layers) if bottom else max(L.index for L in fab.layers)
        zs = data.pos[data.layer == outer, 2]
        if len(zs) == 0:
            raise MeasureError("%s: layer %d (the outer layer on the loop face) has no nodes"
                               % (data.path, outer))
        loop_z = float(np.median(zs))
    z = data.pos[:, 2]
    beyond = (z < loop_z) if bottom else (z > loop_z)
    b = data.bonds
    sel = yarn[b[:, 0]] & yarn[b[:, 1]] & beyond[b[:, 0]] & beyond[b[:, 1]]
    lb = b[sel]
    if len(lb) == 0:
        return loop_z, []
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    nodes, inv = np.unique(lb, return_inverse=True)
    inv = inv.reshape(-1, 2)
    g = coo_matrix((np.ones(len(lb)), (inv[:, 0], inv[:, 1])), shape=(len(nodes), len(nodes)))
    ncomp, lab = connected_components(g, directed=False)
    adj = [[] for _ in nodes]
    for p, q in inv:
        adj[p].append(q)
        adj[q].append(p)
    loops = []
    for c in range(ncomp):
        members = np.nonzero(lab == c)[0]
        ends = [m for m in members if len(adj[m]) == 1]
        if len(ends) != 2 or any(len(adj[m]) > 2 for m in members):
            continue        # a closed ring or a branched piece is no loop between two holes
        # walk from one end to the other, summing the minimum-image steps (the path unwrapped)
        prev, cur = -1, ends[0]
        path = [np.zeros(2)]
        while True:
            nxt = [q for q in adj[cur] if q != prev]
            if not nxt:
                break
            q = nxt[0]
            step = data.min_image(data.pos[nodes[q], :2] - data.pos[nodes[cur], :2])
            path.append(path[-1] + step)
            prev, cur = cur, q
        path = np.array(path)
        seg = np.diff(path, axis=0)
        length = float(np.hypot(*seg.T).sum())
        # the long axis: principal direction of sum_k l_k t_k t_k = sum_k s_k s_k / |s_k|
        ln = np.maximum(np.hypot(*seg.T), 1e-300)
        a2 = (seg[:, :, None] * seg[:, None, :] / ln[:, None, None]).sum(axis=0)
        w, vec = np.linalg.eigh(a2)
        axis = vec[:, 1]
        proj = path @ axis
        extent = float(proj.max() - proj.min())
        if extent < min_length:
            continue
        start = data.pos[nodes[ends[0]], :2]
        mid = start + 0.5 * path[-1]
        tilt = float(wrap_deviation(math.degrees(math.atan2(axis[1], axis[0]))))
        loops.append(dict(x=float(mid[0]), y=float(mid[1]), chord=extent, length=length,
                          tilt=tilt))
    return loop_z, loops


# ----------------------------------------------------------------------------- one layer

def measure_layer(data, fab, L, needles, resolution, capture, min_area, channel_search):
    grid = Grid.of(data, resolution)
    n = len(layer_bonds(data, L.index))
    if n == 0:
        raise MeasureError("%s: layer %d has no bonds (no chain of that layer in the file)"
                           % (data.path, L.index))
    top = not (L.index == min(l.index for l in fab.layers) and len(fab.layers) > 1)
    covered, devmap = coverage(data, grid, L.index, L.angle, L.d_c, top=top)
    g = analyse_gaps(grid, covered, needles, L.angle, capture, min_area, channel_search)
    g.update(grid=grid, covered=covered, devmap=devmap, top=top)
    return g


# ----------------------------------------------------------------------------- pictures

def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def plot_map(path, data, L, res, needles, map_range, title):
    plt = _plt()
    from matplotlib import colors
    grid = res["grid"]
    mm = 1e3
    ext = [grid.xlo * mm, (grid.xlo + grid.lx) * mm, grid.ylo * mm, (grid.ylo + grid.ly) * mm]
    aspect = grid.ly / grid.lx
    w = 6.5 if aspect <= 1.6 else max(2.0, 10.0 / aspect)     # map width [in]
    hgt = max(3.0, min(14.0, w * aspect + 1.0))
    fig, ax = plt.subplots(figsize=(w + 2.2, hgt), dpi=150)
    cmap = plt.get_cmap("jet").copy()
    cmap.set_bad("black")
    dm = np.ma.masked_invalid(np.where(res["covered"], res["devmap"], np.nan))
    im = ax.imshow(dm, origin="lower", extent=ext, cmap=cmap, vmin=-map_range, vmax=map_range,
                   interpolation="nearest")
    fig.colorbar(im, ax=ax, label="local deviation from %g deg [deg]  (black: uncovered)" % L.angle,
                 shrink=0.8)
    kinds = {"crack": ("white", 1.0), "channel": ("magenta", 1.0), "gap": ("0.6", 0.5)}
    clab = res["clab"]
    x, y = grid.centres()
    for kind, (col, lw) in kinds.items():
        ids = [n for n, c in enumerate(res["comps"], 1) if c["kind"] == kind]
        if not ids:
            continue
        mask = np.isin(clab, ids).astype(float)
        ax.contour(x * mm, y * mm, mask, levels=[0.5], colors=[col], linewidths=lw)
    for p in res["points"]:
        if p["kind"] == "crack":
            ax.plot(p["x"] * mm, p["y"] * mm, "w+", ms=6)
            ax.annotate("L %.2f\nW %.2f" % (p["length"] * mm, p["width"] * mm),
                        (p["x"] * mm, p["y"] * mm), xytext=(4, 4), textcoords="offset points",
                        color="white", fontsize=7,
                        bbox=dict(fc="black", alpha=0.5, lw=0, pad=1))
        elif p["kind"] == "covered":
            ax.plot(p["x"] * mm, p["y"] * mm, "o", mfc="none", mec="white", ms=7)
        else:
            ax.plot(p["x"] * mm, p["y"] * mm, "m+", ms=6)
    for c in res["channels"]:
        ax.plot(c["x"] * mm, c["y"] * mm, "m|" if abs(math.sin(math.radians(L.angle))) < 0.7
                else "m_", ms=8)
        ax.annotate("w %.2f" % (c["width"] * mm), (c["x"] * mm, c["y"] * mm), xytext=(3, -10),
                    textcoords="offset points", color="magenta", fontsize=7,
                    bbox=dict(fc="black", alpha=0.5, lw=0, pad=1))
    ax.set_xlabel("x, machine direction [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def plot_histograms(path, fab, layers, orient, rng, bins):
    plt = _plt()
    n = len(layers)
    fig, axs = plt.subplots(1, n, figsize=(4.2 * n, 3.4), dpi=120, squeeze=False)
    for ax, L in zip(axs[0], layers):
        o = orient[L.index]
        c = 0.5 * (o["edges"][1:] + o["edges"][:-1])
        ax.step(c, o["density"], where="mid", color="C0",
                label="measured (mean %.2f, SD %.2f deg)" % (o["mean"], o["sd"]))
        if L.sigma > 0:
            g = np.linspace(-rng, rng, 400)
            ax.plot(g, np.exp(-0.5 * (g / L.sigma) ** 2) / (L.sigma * math.sqrt(2 * math.pi)),
                    "C3--", label="input Gaussian, sigma %.2f deg" % L.sigma)
        ax.set_xlabel("deviation from %g deg [deg]" % L.angle)
        ax.set_ylabel("probability density [1/deg]")
        ax.set_title("layer %d (%g deg), %d file(s)" % (L.index, L.angle, o["files"]), fontsize=9)
        ax.legend(fontsize=7)
        ax.set_xlim(-rng, rng)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


# ----------------------------------------------------------------------------- report

def _ms(vals):
    vals = np.asarray([v for v in vals if np.isfinite(v)], float)
    if len(vals) == 0:
        return 0, float("nan"), float("nan")
    return len(vals), float(vals.mean()), float(vals.std(ddof=1)) if len(vals) > 1 else 0.0


def _fmt(v, scale=1.0, nd=3):
    return "-" if not np.isfinite(v) else ("%.*f" % (nd, v * scale))


def build_rows(fab, layers, orient, defects, loops):
    """Summary rows: (layer, angle, metric, n, mean, sd, unit)."""
    rows = []
    for L in layers:
        o = orient[L.index]
        rows.append((L.index, L.angle, "orientation deviation mean", o["n"], o["mean"], float("nan"), "deg"))
        rows.append((L.index, L.angle, "orientation deviation SD", o["n"], o["sd"], float("nan"), "deg"))
        rows.append((L.index, L.angle, "orientation per chain (mean, SD across chains)", o["chains"],
                     o["chain_mean"], o["chain_sd"], "deg"))
        if L.index not in defects:
            continue
        pts = [p for r in defects[L.index] for p in r["points"]]
        cr = [p for p in pts if p["kind"] == "crack"]
        n, m, s = _ms([p["length"] * 1e3 for p in cr])
        rows.append((L.index, L.angle, "crack length", n, m, s, "mm"))
        n, m, s = _ms([p["width"] * 1e3 for p in cr])
        rows.append((L.index, L.angle, "crack width", n, m, s, "mm"))
        cov = sum(1 for p in pts if p["kind"] == "covered")
        rows.append((L.index, L.angle, "stitching points without a visible crack", len(pts),
                     100.0 * cov / len(pts) if pts else float("nan"), float("nan"), "%"))
        onch = sum(1 for p in pts if p["kind"] == "channel")
        if onch:
            rows.append((L.index, L.angle, "stitching points on a channel", len(pts),
                         100.0 * onch / len(pts), float("nan"), "%"))
        fg = [c for r in defects[L.index] for c in r["comps"] if c["kind"] == "gap"]
        n, m, s = _ms([c["length"] * 1e3 for c in fg])
        rows.append((L.index, L.angle, "other gaps (away from stitching points): length", n, m, s,
                     "mm"))
        n, m, s = _ms([c["width"] * 1e3 for c in fg])
        rows.append((L.index, L.angle, "other gaps (away from stitching points): width", n, m, s,
                     "mm"))
        ch = [c for r in defects[L.index] for c in r["channels"]]
        if ch:
            n, m, s = _ms([c["width"] * 1e3 for c in ch])
            rows.append((L.index, L.angle, "channel width (middle between stitching points)", n, m,
                         s, "mm"))
            op = [c["width"] * 1e3 for c in ch if c["width"] > 0]
            n2, m2, s2 = _ms(op)
            rows.append((L.index, L.angle, "channel width where open", n2, m2, s2, "mm"))
    if loops is not None:
        t = [l["tilt"] for l in loops]
        n, m, s = _ms(t)
        rows.append((0, float("nan"), "loop tilt from x (signed)", n, m, s, "deg"))
        n, m, s = _ms([abs(v) for v in t])
        rows.append((0, float("nan"), "loop tilt from x (magnitude)", n, m, s, "deg"))
    return rows


def write_reports(out, args, fab, layers, orient, defects, loops, rows):
    import csv
    md = []
    md.append("# ncf-measure")
    md.append("")
    md.append("files: %s; fabric: %s; map resolution %.2f um; capture radius %.0f um"
              % (", ".join(args.data), fab.source, args.resolution * 1e6, args.capture * 1e6))
    md.append("")
    md.append("## Orientation (length-weighted, bonds projected on the x-y plane)")
    md.append("")
    md.append("| layer | nominal [deg] | input sigma [deg] | generator's sample mean, std [deg] | "
              "mean deviation [deg] | SD [deg] | bonds | per chain: mean, SD [deg] | chains | files |")
    md.append("|---|---|---|---|---|---|---|---|---|---|")
    for L in layers:
        o = orient[L.index]
        md.append("| %d | %g | %g | %s | %.3f | %.3f | %d | %.4f, %.4f | %d | %d |"
                  % (L.index, L.angle, L.sigma,
                     "-" if L.sampled_std is None else "%.4f, %.4f" % (L.sampled_mean - L.angle,
                                                                      L.sampled_std),
                     o["mean"], o["sd"], o["n"], o["chain_mean"], o["chain_sd"], o["chains"],
                     o["files"]))
    md.append("")
    md.append("## Defects and loops")
    md.append("")
    md.append("| layer | nominal [deg] | metric | n | mean | SD | unit |")
    md.append("|---|---|---|---|---|---|---|")
    for r in rows:
        if r[2].startswith("orientation"):
            continue
        md.append("| %s | %s | %s | %d | %s | %s | %s |"
                  % ("yarn" if r[0] == 0 else r[0], "-" if not np.isfinite(r[1]) else "%g" % r[1],
                     r[2], r[3], _fmt(r[4]), _fmt(r[5]), r[6]))
    text = "\n".join(md) + "\n"
    with open(os.path.join(out, "ncf-measure.md"), "w") as f:
        f.write(text)
    with open(os.path.join(out, "ncf-measure-summary.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["layer", "nominal_deg", "metric", "n", "mean", "sd", "unit"])
        for r in rows:
            w.writerow([r[0], "" if not np.isfinite(r[1]) else r[1], r[2], r[3],
                        "" if not np.isfinite(r[4]) else "%.6g" % r[4],
                        "" if not np.isfinite(r[5]) else "%.6g" % r[5], r[6]])
    with open(os.path.join(out, "ncf-measure-defects.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["file", "layer", "kind", "point", "x_mm", "y_mm", "length_mm", "width_mm",
                    "area_mm2", "tilt_deg"])
        for L in layers:
            for k, r in enumerate(defects.get(L.index, [])):
                for p in r["points"]:
                    w.writerow([args.data[k], L.index, p["kind"], p["index"], "%.5f" % (p["x"] * 1e3),
                                "%.5f" % (p["y"] * 1e3),
                                "%.5f" % (p["length"] * 1e3) if "length" in p else "",
                                "%.5f" % (p["width"] * 1e3) if "width" in p else "",
                                "%.6f" % (p["area"] * 1e6) if "area" in p else "", ""])
                for c in r["channels"]:
                    w.writerow([args.data[k], L.index, "channel-middle", c["index"],
                                "%.5f" % (c["x"] * 1e3), "%.5f" % (c["y"] * 1e3), "",
                                "%.5f" % (c["width"] * 1e3), "", ""])
                for c in r["comps"]:
                    if c["kind"] == "gap":
                        w.writerow([args.data[k], L.index, "gap", c["needle"], "", "",
                                    "%.5f" % (c["length"] * 1e3), "%.5f" % (c["width"] * 1e3),
                                    "%.6f" % (c["area"] * 1e6), ""])
        for k, l in (loops or []):
            w.writerow([args.data[k], "yarn", "loop", "", "%.5f" % (l["x"] * 1e3),
                        "%.5f" % (l["y"] * 1e3), "%.5f" % (l["chord"] * 1e3), "", "",
                        "%.4f" % l["tilt"]])
    with open(os.path.join(out, "ncf-measure-orientation.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["deviation_deg"] + ["density_layer%d_per_deg" % L.index for L in layers])
        e = orient[layers[0].index]["edges"]
        c = 0.5 * (e[1:] + e[:-1])
        for k in range(len(c)):
            w.writerow(["%.4f" % c[k]] + ["%.6g" % orient[L.index]["density"][k] for L in layers])
    return text


# ----------------------------------------------------------------------------- command line

class _Parser(argparse.ArgumentParser):
    def error(self, message):
        self.print_usage(sys.stderr)
        sys.stderr.write("ncf-measure: ERROR: %s\n" % message)
        sys.exit(1)


def _length(text):
    try:
        return _length_text(text)
    except ValueError as e:
        raise argparse.ArgumentTypeError(str(e))


def finite_arg(text):
    """argparse type: a finite number (also used by ncf-export and ncf-perm)."""
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError("'%s' is not a number" % text)
    if not math.isfinite(v):
        raise argparse.ArgumentTypeError("'%s' is not a finite number" % text)
    return v


def int_arg(text):
    """argparse type: an integer (also used by ncf-export and ncf-perm)."""
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError("'%s' is not an integer" % text)


def parse_args(argv):
    p = _Parser(prog="ncf-measure",
                description="Measure orientation and defects of an NCF data file (doc/ncf_measure.md).")
    p.add_argument("data", nargs="+", help="LAMMPS data file(s), atom_style bond, with NCF_NODE; "
                   "several files (seeds) are averaged")
    p.add_argument("--needles", action="append", required=True,
                   help="stitching points (PREFIX.needles); once, or once per data file")
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--summary", help="the generator's PREFIX.summary (angles, sigmas, d_c)")
    src.add_argument("--card", help="the fabric card (angles, sigmas, chain_diameter)")
    p.add_argument("--yarn", help="a yarn data file to append (e.g. PREFIX.yarn.data; one DATA only)")
    p.add_argument("--out", default="ncf-measure", help="output folder (default ./ncf-measure)")
    p.add_argument("--layers", help="comma-separated layer indices to measure (default all)")
    p.add_argument("--resolution", type=_length, default=5e-6,
                   help="map pixel size, at most 10 um (default 5 um)")
    p.add_argument("--capture", type=_length, default=0.15e-3,
                   help="a gap within this distance of a stitching point belongs to it (default 0.15 mm)")
    p.add_argument("--channel-search", type=_length, default=0.3e-3,
                   help="channel runs counted when they reach within this distance of the middle "
                   "on the line across (default 0.3 mm)")
    p.add_argument("--min-gap", type=finite_arg, default=None,
                   help="smallest gap area counted [mm^2] (default (d_c/2)^2)")
    p.add_argument("--loop-z", type=_length, default=None,
                   help="z beyond which yarn nodes are on the loop face (default the middle of the "
                   "outer layer on that face)")
    p.add_argument("--min-loop", type=_length, default=0.2e-3,
                   help="shortest loop chord counted (default 0.2 mm)")
    p.add_argument("--range", type=finite_arg, default=15.0, help="histogram half-width [deg] (default 15)")
    p.add_argument("--bins", type=int_arg, default=60, help="histogram bins (default 60)")
    p.add_argument("--map-range", type=finite_arg, default=10.0,
                   help="colour range of the deviation maps [deg] (default 10)")
    p.add_argument("--no-defects", action="store_true", help="orientation only")
    p.add_argument("--no-pictures", action="store_true", help="tables only")
    p.add_argument("-q", "--quiet", action="store_true", help="do not print the table")
    a = p.parse_args(join_negative_values(argv, ("--resolution", "--capture", "--channel-search",
                                                 "--min-gap", "--loop-z", "--min-loop", "--range",
                                                 "--bins", "--map-range")))
    if not (0 < a.resolution <= 10e-6 + 1e-15):
        p.error("--resolution %g m: must be > 0 and at most 10 um" % a.resolution)
    if a.capture <= 0 or a.channel_search <= 0 or a.min_loop < 0:
        p.error("--capture, --channel-search must be > 0, --min-loop >= 0")
    if not (0 < a.range <= 90) or a.bins < 1 or a.map_range <= 0:
        p.error("--range must be in (0, 90], --bins >= 1, --map-range > 0")
    if len(a.needles) not in (1, len(a.data)):
        p.error("--needles given %d times for %d data files (give it once or once per file)"
                % (len(a.needles), len(a.data)))
    if a.yarn and len(a.data) != 1:
        p.error("--yarn needs exactly one DATA file")
    if a.min_gap is not None and not a.min_gap > 0:
        p.error("--min-gap %g mm^2: must be > 0" % a.min_gap)
    if a.bins > 100000:
        p.error("--bins %d: at most 100000" % a.bins)
    if os.path.exists(a.out) and not os.path.isdir(a.out):
        p.error("--out %s: exists and is not a folder (the output folder)" % a.out)
    return a


def run(args):
    fab = read_summary(args.summary) if args.summary else read_card(args.card)
    layers = fab.layers
    if args.layers:
        try:
            want = [int(t) for t in args.layers.split(",") if t.strip()]
        except ValueError:
            raise MeasureError("--layers '%s': expected comma-separated layer indices" % args.layers)
        for w in want:
            if fab.layer(w) is None:
                raise MeasureError("--layers: unknown layer %d (%s has layers %s)"
                                   % (w, fab.source, ", ".join(str(L.index) for L in fab.layers)))
        layers = [fab.layer(w) for w in want]
    needles = [read_needles(n) for n in args.needles]
    # every input read and checked before anything is written
    datas = []
    for k, path in enumerate(args.data):
        data = read_data(path)
        if args.yarn:
            data.append(read_data(args.yarn))
        check_layers(data, fab)
        nd = needles[k if len(needles) > 1 else 0]
        src = args.needles[k if len(needles) > 1 else 0]
        check_fabric(data, fab, path, nd, src)
        out_of_box = (nd[:, 0] < data.lo[0] - 1e-12) | (nd[:, 0] > data.hi[0] + 1e-12) | \
            (nd[:, 1] < data.lo[1] - 1e-12) | (nd[:, 1] > data.hi[1] + 1e-12)
        if np.any(out_of_box):
            q = nd[np.nonzero(out_of_box)[0][0]]
            raise MeasureError("%s: stitching point (%g, %g) lies outside the box of %s "
                               "(x %g..%g, y %g..%g): needles of another RVE?"
                               % (src, q[0], q[1], path, data.lo[0], data.hi[0], data.lo[1], data.hi[1]))
        datas.append(data)
    try:
        os.makedirs(args.out, exist_ok=True)
    except OSError as e:
        raise MeasureError("--out %s: cannot create the output folder: %s" % (args.out, e.strerror or e))
    orient_parts = {L.index: [] for L in layers}
    defects = {}
    all_loops = []
    any_yarn = False
    for k, path in enumerate(args.data):
        data = datas[k]
        nd = needles[k if len(needles) > 1 else 0]
        for L in layers:
            dev, w = layer_orientation(data, L.index, L.angle)
            if len(dev) == 0:
                raise MeasureError("%s: layer %d has no bonds (no chain of that layer in the file)"
                                   % (path, L.index))
            orient_parts[L.index].append((dev, w, chain_angles(data, L.index, L.angle)))
            if not args.no_defects:
                min_area = (0.5 * L.d_c) ** 2 if args.min_gap is None else args.min_gap * 1e-6
                res = measure_layer(data, fab, L, nd, args.resolution, args.capture, min_area,
                                    args.channel_search)
                defects.setdefault(L.index, []).append(res)
                if not args.no_pictures:
                    stem = os.path.splitext(os.path.basename(path))[0]
                    plot_map(os.path.join(args.out, "%s-layer%d-map.png" % (stem, L.index)), data,
                             L, res, nd, args.map_range,
                             "%s: layer %d (%g deg)\nseen from the %s, other layers and yarn removed"
                             % (os.path.basename(path), L.index, L.angle,
                                "top" if res["top"] else "bottom"))
        if (data.layer == 0).any():
            any_yarn = True
            _, lp = loop_tilts(data, fab, args.loop_z, args.min_loop)
            all_loops += [(k, l) for l in lp]
    orient = {}
    for L in layers:
        parts = orient_parts[L.index]
        dev = np.concatenate([p[0] for p in parts])
        w = np.concatenate([p[1] for p in parts])
        m, s = weighted_stats(dev, w)
        ca = np.concatenate([p[2] for p in parts])
        dens = [density(p[0], p[1], args.bins, args.range) for p in parts]
        orient[L.index] = dict(mean=m, sd=s, n=len(dev), files=len(parts), edges=dens[0][0],
                               density=np.mean([d[1] for d in dens], axis=0),
                               per_file=[weighted_stats(p[0], p[1]) for p in parts],
                               chains=len(ca), chain_mean=float(np.mean(ca)),
                               chain_sd=float(np.std(ca, ddof=1)) if len(ca) > 1 else 0.0)
    rows = build_rows(fab, layers, orient, defects, [l for _, l in all_loops] if any_yarn else None)
    text = write_reports(args.out, args, fab, layers, orient, defects,
                         all_loops if any_yarn else None, rows)
    if not args.no_pictures:
        plot_histograms(os.path.join(args.out, "ncf-measure-orientation.png"), fab, layers, orient,
                        args.range, args.bins)
    if not args.quiet:
        sys.stdout.write(text)
    return dict(fab=fab, orient=orient, defects=defects, loops=[l for _, l in all_loops], rows=rows)


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    try:
        run(args)
    except MeasureError as e:
        sys.stderr.write("ncf-measure: ERROR: %s\n" % e)
        return 1
    except (OSError, ValueError, IndexError, KeyError) as e:
        # (a file that cannot be written, a value numpy refuses: said, without a traceback)
        sys.stderr.write("ncf-measure: ERROR: %s\n" % describe_error(e))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
