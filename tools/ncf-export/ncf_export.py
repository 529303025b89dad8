#!/usr/bin/python3
"""ncf-export: a fabric data file as VTK files that ParaView and meshio read.

  --vtu FILE           every chain and yarn bond as a VTK line cell (VTU), point data layer,
                       chain, yarn (0/1), radius [m], tangent; chains unwrapped across the
                       periodic faces so that each is continuous
  --vti FILE --voxel H a periodic voxel grid over the RVE (VTK ImageData): cell arrays vf (fibre
                       volume fraction, chain cylinders x packing, sub-sampled), dir (mean fibre
                       direction), a2 (orientation tensor), phase (0 void, 1..N layer, N+1 yarn)
  --vtk FILE           the same grid as legacy STRUCTURED_POINTS (for readers without .vti)

Reads LAMMPS data files of atom_style bond or angle (ncf-gen's, write_data of any stage) and the
generator's summary (chain diameters, packings, filaments per chain). doc/ncf_export.md. Only
Debian's python3-numpy and python3-vtk9 are used.
"""

import argparse
import math
import os
import re
import sys

import numpy as np

# the data-file reader is ncf-measure's (tools/ncf-measure/ncf_measure.py, beside this tool)
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "ncf-measure"))
import ncf_measure  # noqa: E402


class ExportError(Exception):
    """Input the tool cannot export; the message names the file, line/option and value."""


_LENGTH = {"m": 1.0, "mm": 1e-3, "um": 1e-6, "micron": 1e-6}


def length(text, opt, signed=False):
    """'40um', '0.04 mm', '4e-5' (metres) -> metres; > 0 unless signed."""
    m = re.fullmatch(r"\s*([-+0-9.eE]+)\s*([a-z]*)\s*", text)
    if not m:
        raise ExportError("ncf-export: option %s: value '%s' is not a length (e.g. 40um, 0.04mm, 4e-5)"
                          % (opt, text))
    try:
        v = float(m.group(1))
    except ValueError:
        raise ExportError("ncf-export: option %s: value '%s' is not a number" % (opt, text))
    u = m.group(2) or "m"
    if u not in _LENGTH:
        raise ExportError("ncf-export: option %s: value '%s': unknown unit '%s' (m, mm, um)" % (opt, text, u))
    v *= _LENGTH[u]
    if not math.isfinite(v) or (not signed and not (v > 0)):
        raise ExportError("ncf-export: option %s: value '%s' must be > 0" % (opt, text))
    return v


# ----------------------------------------------------------------------------- inputs

class Kind:
    """Chain cross-section of one atom type: contact diameter, packing, filament radius."""

    def __init__(self, name, d, packing, filaments=None):
        self.name = name
        self.d = d
        self.packing = packing
        # filament radius: packing d^2 = n d_f^2
        self.rf = 0.5 * d * math.sqrt(packing / filaments) if filaments else None


def read_summary(path):
    """Layers (type i = layer i, bottom first) and the yarn (last type) from PREFIX.summary."""
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            lines = f.read().splitlines()
    except OSError as e:
        raise ExportError("ncf-export: cannot read the summary %s: %s" % (path, e.strerror or e))
    layers, yarn, cur = [], None, None
    unit = {"m": 1.0, "mm": 1e-3, "um": 1e-6}
    for n, line in enumerate(lines, 1):
        s = line.strip()
        m = re.match(r"layer (\d+) \(atom/bond type (\d+)\)$", s)
        if m:
            cur = {"index": int(m.group(1)), "type": int(m.group(2)), "line": n}
            layers.append(cur)
            continue
        m = re.match(r"stitching yarn \(atom/bond type (\d+)\)", s)
        if m:
            cur = {"index": 0, "type": int(m.group(1)), "line": n}
            yarn = cur
            continue
        if cur is None:
            continue
        m = re.match(r"chain d_c, packing\s+(\S+) (\S+), (\S+)$", s) or \
            re.match(r"chain diameter, packing\s+(\S+) (\S+), (\S+)$", s)
        if m and m.group(2) in unit:
            cur["d"] = float(m.group(1)) * unit[m.group(2)]
            cur["packing"] = float(m.group(3))
            continue
        m = re.match(r"chain diameter \(hexagonal packing\)\s+(\S+) (\S+)", s)
        if m and m.group(2).rstrip(",") in unit:
            cur["d"] = float(m.group(1)) * unit[m.group(2).rstrip(",")]
            cur["packing"] = math.pi / (2 * math.sqrt(3))
            continue
        m = re.match(r"filaments per chain\s+(\S+)", s)
        if m:
            cur["filaments"] = float(m.group(1))
    if not layers:
        raise ExportError("ncf-export: %s: no 'layer N (atom/bond type N)' block: not a summary of ncf-gen"
                          % path)
    kinds = {}
    for b in layers + ([yarn] if yarn else []):
        if "d" not in b:
            raise ExportError("ncf-export: %s:%d: block without a 'chain d_c, packing' line" % (path, b["line"]))
        kinds[b["type"]] = (b["index"], Kind("yarn" if b["index"] == 0 else "layer %d" % b["index"],
                                             b["d"], b["packing"], b.get("filaments")))
    return kinds, len(layers)


def summary_atoms(path):
    """The number of nodes of the generated fabric, layers and yarn ('total atoms, bonds N, M')."""
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            m = re.match(r"\s*total atoms, bonds\s+(\d+), (\d+)", line)
            if m:
                return int(m.group(1))
    return None


def read_data(path):
    """LAMMPS data file, atom_style bond or angle (columns id mol type x y z [ix iy iz]), with or
    without the NCF_NODE section: ncf-measure's reader (one reader of the package's data files)."""
    try:
        return ncf_measure.read_data(path, need_nodes=False)
    except ncf_measure.MeasureError as e:
        raise ExportError("ncf-export: %s" % e)


def append(d, o):
    """Append a second data file (the generator's yarn.data) to d."""
    try:
        d.append(o)
    except ncf_measure.MeasureError as e:
        raise ExportError("ncf-export: %s" % e)


# ----------------------------------------------------------------------------- geometry

def min_image(d, v):
    v = np.array(v, dtype=float, copy=True)
    for ax in (0, 1):
        L = d.hi[ax] - d.lo[ax]
        v[..., ax] -= L * np.round(v[..., ax] / L)
    return v


def unwrap(d):
    """Chains continuous across the periodic x/y faces: positions by a walk along the bonds from
    each chain's lowest atom ID (kept where the file has it). Returns (positions, bond end points
    (M, 2, 3)): every bond's second end at the minimum image of its first, so that a bond that
    closes a loop through a face (the stitching yarn) keeps its true length."""
    n = len(d.ids)
    pos = d.pos.copy()
    for ax in (0, 1):
        L = d.hi[ax] - d.lo[ax]
        pos[:, ax] = d.lo[ax] + np.mod(pos[:, ax] - d.lo[ax], L)
    adj = [[] for _ in range(n)]
    for a, b in d.bonds:
        adj[a].append(b)
        adj[b].append(a)
    out = np.full((n, 3), np.nan)
    order = np.argsort(d.ids)
    for root in order:
        if not np.isnan(out[root, 0]):
            continue
        out[root] = pos[root]
        stack = [root]
        while stack:
            a = stack.pop()
            for b in adj[a]:
                if np.isnan(out[b, 0]):
                    out[b] = out[a] + min_image(d, pos[b] - pos[a])
                    stack.append(b)
    a, b = d.bonds[:, 0], d.bonds[:, 1]
    ends = np.stack([out[a], out[a] + min_image(d, out[b] - out[a])], 1) if len(a) else np.zeros((0, 2, 3))
    return out, ends


def node_kinds(d, kinds, nlayers):
    """layer index per atom (0 = yarn) and the Kind per atom."""
    known = sorted(kinds)
    bad = ~np.isin(d.type, known)
    if np.any(bad):
        k = int(np.nonzero(bad)[0][0])
        raise ExportError("ncf-export: %s: atom %d has type %d, the summary has types %s"
                          % (d.path, d.ids[k], d.type[k], ", ".join(map(str, known))))
    layer = np.array([kinds[t][0] for t in d.type], dtype=np.int64)
    return layer


# ----------------------------------------------------------------------------- VTU

def write_vtu(d, kinds, path, quiet):
    vtk, ns = _vtk()
    layer = node_kinds(d, kinds, None)
    out, ends = unwrap(d)
    M = len(d.bonds)
    a, b = d.bonds[:, 0], d.bonds[:, 1]
    # points: every atom at its unwrapped position; a bond whose second end is not there (a loop
    # closed through a face) gets a copy of that atom at the image it needs
    far = np.linalg.norm(ends[:, 1] - out[b], axis=1) > 1e-9 * max(d.hi[0] - d.lo[0], 1e-30) if M else np.zeros(0, bool)
    extra = np.nonzero(far)[0]
    P = np.concatenate([out, ends[extra, 1]]) if len(extra) else out
    src = np.concatenate([np.arange(len(out)), b[extra]])    # atom of each point
    second = b.copy()
    second[extra] = len(out) + np.arange(len(extra))
    # tangent per atom: the axis of its bonds (principal direction of the sum of u u^T over its
    # bonds, so that the order of a bond's two atoms in the file does not matter)
    T = np.zeros((len(out), 3, 3))
    if M:
        v = ends[:, 1] - ends[:, 0]
        ln = np.linalg.norm(v, axis=1)
        u = v / np.where(ln > 0, ln, 1)[:, None]
        uu = u[:, :, None] * u[:, None, :]
        np.add.at(T, a, uu)
        np.add.at(T, b, uu)
    _, ev = np.linalg.eigh(T)
    tan = ev[:, :, 2]
    big = np.argmax(np.abs(tan), axis=1)
    tan *= np.sign(tan[np.arange(len(tan)), big])[:, None]
    tan[np.trace(T, axis1=1, axis2=2) == 0] = 0.0
    radius = np.array([kinds[t][1].d / 2 for t in d.type])
    pts = vtk.vtkPoints()
    pts.SetData(ns.numpy_to_vtk(np.ascontiguousarray(P), deep=1))
    ug = vtk.vtkUnstructuredGrid()
    ug.SetPoints(pts)
    conn = np.empty((M, 3), dtype=np.int64)
    conn[:, 0] = 2
    conn[:, 1] = a
    conn[:, 2] = second
    cells = vtk.vtkCellArray()
    cells.SetCells(M, ns.numpy_to_vtkIdTypeArray(conn.reshape(-1), deep=1))
    ug.SetCells(vtk.VTK_LINE, cells)

    def add(name, arr, where):
        x = ns.numpy_to_vtk(np.ascontiguousarray(arr), deep=1)
        x.SetName(name)
        where.AddArray(x)

    pd = ug.GetPointData()
    add("layer", layer[src].astype(np.int32), pd)
    add("chain", d.mol[src].astype(np.int32), pd)
    add("yarn", (layer[src] == 0).astype(np.int32), pd)
    add("radius", radius[src], pd)
    add("tangent", tan[src], pd)
    add("atom_id", d.ids[src].astype(np.int64), pd)
    pd.SetActiveScalars("radius")
    fd = ug.GetFieldData()
    add("ncf_box", np.array([d.lo[0], d.hi[0], d.lo[1], d.hi[1], d.lo[2], d.hi[2]]), fd)
    w = vtk.vtkXMLUnstructuredGridWriter()
    w.SetFileName(path)
    w.SetInputData(ug)
    if not w.Write():
        raise ExportError("ncf-export: option --vtu: cannot write '%s'" % path)
    if not quiet:
        print("ncf-export: %d bonds as line cells, %d points (%d copies where a loop closes through a "
              "face) -> %s" % (M, len(P), len(extra), path))
    return M


# ----------------------------------------------------------------------------- voxel grid

def voxelize(d, kinds, nlayers, h, sub, zrange=None, chunk=4_000_000):
    """Per-cell vf, direction-weighted sums, phase volumes on the periodic grid."""
    layer = node_kinds(d, kinds, nlayers)
    out, ends = unwrap(d)
    Lx, Ly = d.hi[0] - d.lo[0], d.hi[1] - d.lo[1]
    a, b = d.bonds[:, 0], d.bonds[:, 1]
    rad = np.array([kinds[t][1].d / 2 for t in d.type])[a]
    pack = np.array([kinds[t][1].packing for t in d.type])[a]
    # the bond's phase: its layer (both ends in one layer), the yarn N+1
    la = layer[a]
    phase = np.where(la == 0, nlayers + 1, la)
    if zrange is None:
        zlo = float(np.min(out[:, 2] - np.array([kinds[t][1].d / 2 for t in d.type])))
        zhi = float(np.max(out[:, 2] + np.array([kinds[t][1].d / 2 for t in d.type])))
    else:
        zlo, zhi = zrange
    n = [int(math.ceil(Lx / h - 1e-9)), int(math.ceil(Ly / h - 1e-9)), int(math.ceil((zhi - zlo) / h - 1e-9))]
    n = [max(m, 1) for m in n]
    if n[0] * n[1] * n[2] > 3e8:
        raise ExportError("ncf-export: option --voxel: %g m gives %d x %d x %d = %.3g cells (at most 3e8)"
                          % (h, n[0], n[1], n[2], float(n[0]) * n[1] * n[2]))
    sp = [Lx / n[0], Ly / n[1], (zhi - zlo) / n[2]]
    org = np.array([d.lo[0], d.lo[1], zlo])
    N = n[0] * n[1] * n[2]
    vf = np.zeros(N)
    a2 = np.zeros((N, 6))
    ph = np.zeros((N, nlayers + 2))
    P0 = ends[:, 0]
    v = ends[:, 1] - ends[:, 0]
    L = np.linalg.norm(v, axis=1)
    ok = L > 0
    t = np.zeros_like(v)
    t[ok] = v[ok] / L[ok, None]
    s1 = (np.arange(sub) + 0.5) / sub
    so = np.stack(np.meshgrid(s1, s1, s1, indexing="ij"), -1).reshape(-1, 3)    # (S, 3) in cells
    S = len(so)
    spv = np.array(sp)
    # voxel index range of each bond's cylinder
    lo = np.minimum(ends[:, 0], ends[:, 1]) - rad[:, None]
    hi = np.maximum(ends[:, 0], ends[:, 1]) + rad[:, None]
    i0 = np.floor((lo - org) / spv).astype(np.int64)
    i1 = np.floor((hi - org) / spv).astype(np.int64)
    ext = i1 - i0 + 1
    tt = np.stack([t[:, 0] ** 2, t[:, 1] ** 2, t[:, 2] ** 2, t[:, 0] * t[:, 1], t[:, 1] * t[:, 2],
                   t[:, 0] * t[:, 2]], 1)
    shapes = {}
    for k in np.nonzero(ok)[0]:
        shapes.setdefault(tuple(ext[k]), []).append(k)
    for shape, ks in shapes.items():
        ks = np.array(ks)
        off = np.stack(np.meshgrid(np.arange(shape[0]), np.arange(shape[1]), np.arange(shape[2]),
                                   indexing="ij"), -1).reshape(-1, 3)    # (V, 3)
        V = len(off)
        per = max(1, chunk // (V * S))
        for c0 in range(0, len(ks), per):
            kk = ks[c0:c0 + per]
            cell = i0[kk][:, None, :] + off[None, :, :]                  # (B, V, 3) unwrapped index
            q = org + (cell[:, :, None, :] + so[None, None, :, :]) * spv   # (B, V, S, 3)
            w = q - P0[kk][:, None, None, :]
            pr = np.einsum("bvsk,bk->bvs", w, t[kk])
            perp2 = np.einsum("bvsk,bvsk->bvs", w, w) - pr * pr
            ins = (pr >= 0) & (pr <= L[kk][:, None, None]) & (perp2 <= (rad[kk] ** 2)[:, None, None])
            frac = ins.sum(axis=2) / S * pack[kk][:, None]               # (B, V)
            cx = np.mod(cell[..., 0], n[0])
            cy = np.mod(cell[..., 1], n[1])
            cz = np.mod(cell[..., 2], n[2])
            flat = (cx + n[0] * (cy + n[1] * cz)).reshape(-1)
            fr = frac.reshape(-1)
            m = fr > 0
            flat, fr = flat[m], fr[m]
            bi = np.repeat(np.arange(len(kk)), V)[m]
            np.add.at(vf, flat, fr)
            np.add.at(a2, flat, fr[:, None] * tt[kk][bi])
            np.add.at(ph, (flat, phase[kk][bi]), fr)
    return n, sp, org, vf, a2, ph


def write_vti(d, kinds, nlayers, h, sub, vti, legacy, zrange, quiet):
    vtk, ns = _vtk()
    n, sp, org, vsum, a2s, ph = voxelize(d, kinds, nlayers, h, sub, zrange)
    N = len(vsum)
    vf = np.minimum(vsum, 1.0)
    occ = vsum > 0
    a2 = np.zeros((N, 6))
    a2[occ] = a2s[occ] / vsum[occ, None]
    dirv = np.zeros((N, 3))
    if np.any(occ):
        A = np.zeros((int(occ.sum()), 3, 3))
        x = a2[occ]
        A[:, 0, 0], A[:, 1, 1], A[:, 2, 2] = x[:, 0], x[:, 1], x[:, 2]
        A[:, 0, 1] = A[:, 1, 0] = x[:, 3]
        A[:, 1, 2] = A[:, 2, 1] = x[:, 4]
        A[:, 0, 2] = A[:, 2, 0] = x[:, 5]
        wv, ev = np.linalg.eigh(A)
        e = ev[:, :, 2]
        big = np.argmax(np.abs(e), axis=1)
        e *= np.sign(e[np.arange(len(e)), big])[:, None]
        dirv[occ] = e
    phase = np.where(occ, np.argmax(ph, axis=1), 0).astype(np.int32)
    img = vtk.vtkImageData()
    img.SetDimensions(n[0] + 1, n[1] + 1, n[2] + 1)
    img.SetSpacing(*sp)
    img.SetOrigin(*org)

    def add(name, arr, where):
        x = ns.numpy_to_vtk(np.ascontiguousarray(arr), deep=1)
        x.SetName(name)
        where.AddArray(x)

    cd = img.GetCellData()
    add("vf", vf, cd)
    add("dir", dirv, cd)
    add("a2", a2, cd)
    add("phase", phase, cd)
    cd.SetActiveScalars("vf")
    # the filament radius of the layers (Gebart's permeability in ncf-perm); one value: the
    # volume-weighted mean of the layers'
    rfs = [(k.rf, k.packing) for t, (li, k) in kinds.items() if li > 0 and k.rf]
    fd = img.GetFieldData()
    if rfs:
        add("ncf_fibre_radius", np.array([float(np.mean([r for r, _ in rfs]))]), fd)
    add("ncf_box", np.array([d.lo[0], d.hi[0], d.lo[1], d.hi[1], org[2], org[2] + n[2] * sp[2]]), fd)
    fibre_volume = float(np.sum(vsum) * sp[0] * sp[1] * sp[2])
    add("ncf_fibre_volume", np.array([fibre_volume]), fd)
    if vti:
        w = vtk.vtkXMLImageDataWriter()
        w.SetFileName(vti)
        w.SetInputData(img)
        if not w.Write():
            raise ExportError("ncf-export: option --vti: cannot write '%s'" % vti)
    if legacy:
        w = vtk.vtkStructuredPointsWriter()
        w.SetFileName(legacy)
        w.SetInputData(img)
        w.SetFileTypeToBinary()
        w.SetFileVersion(42)          # the legacy 4.2 format without array metadata: meshio reads it
        w.WriteArrayMetaDataOff()
        if not w.Write():
            raise ExportError("ncf-export: option --vtk: cannot write '%s'" % legacy)
    if not quiet:
        print("ncf-export: voxel grid %d x %d x %d cells of %.4g x %.4g x %.4g um (z %.4g .. %.4g mm, "
              "periodic), fibre volume %.6g mm^3, mean vf %.4f, %d cells clipped at vf = 1 -> %s"
              % (n[0], n[1], n[2], sp[0] * 1e6, sp[1] * 1e6, sp[2] * 1e6, org[2] * 1e3,
                 (org[2] + n[2] * sp[2]) * 1e3, fibre_volume * 1e9, float(vf.mean()),
                 int(np.sum(vsum > 1)), ", ".join(x for x in (vti, legacy) if x)))
    return n, sp, vf


def chain_volume(d, kinds):
    """Sum over bonds of length x pi r^2 x packing (the fibre volume the grid must hold)."""
    out, ends = unwrap(d)
    a = d.bonds[:, 0]
    L = np.linalg.norm(ends[:, 1] - ends[:, 0], axis=1)
    r = np.array([kinds[t][1].d / 2 for t in d.type])[a]
    p = np.array([kinds[t][1].packing for t in d.type])[a]
    return float(np.sum(L * math.pi * r * r * p))


def _vtk():
    try:
        import vtk
        from vtk.util import numpy_support
    except ImportError as e:
        raise ExportError("ncf-export: the Python VTK module is missing (Debian package python3-vtk9): %s" % e)
    return vtk, numpy_support


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        self.print_usage(sys.stderr)
        sys.stderr.write("ncf-export: error: %s\n" % message)
        sys.exit(2)


def parse_args(argv):
    p = _Parser(prog="ncf-export", description=__doc__.split("\n")[0])
    p.add_argument("data", help="LAMMPS data file (atom_style bond or angle)")
    p.add_argument("--summary", required=True, help="the generator's PREFIX.summary (diameters, packings)")
    p.add_argument("--yarn", help="a second data file appended (e.g. PREFIX.yarn.data)")
    p.add_argument("--vtu", help="write the chains as line cells to this .vtu")
    p.add_argument("--vti", help="write the voxel grid to this .vti (needs --voxel)")
    p.add_argument("--vtk", help="write the voxel grid as legacy STRUCTURED_POINTS to this .vtk")
    p.add_argument("--voxel", help="largest voxel edge, e.g. 40um (the cells tile the box exactly)")
    p.add_argument("--subsample", type=ncf_measure.int_arg, default=4,
                   help="sub-points per voxel edge for the volume fractions (default 4: 64 per voxel)")
    p.add_argument("--z-range", metavar="ZLO,ZHI",
                   help="z extent of the grid, e.g. --z-range=-0.1mm,0.9mm (default: the chains' "
                        "extent, lowest to highest chain surface)")
    p.add_argument("-q", "--quiet", action="store_true")
    return p.parse_args(ncf_measure.join_negative_values(argv, ("--voxel", "--subsample", "--z-range")))


def main(argv=None):
    a = parse_args(sys.argv[1:] if argv is None else argv)
    try:
        if not (a.vtu or a.vti or a.vtk):
            raise ExportError("ncf-export: nothing to write: give --vtu FILE and/or --vti FILE / --vtk FILE")
        if (a.vti or a.vtk) and not a.voxel:
            raise ExportError("ncf-export: option --vti/--vtk: needs --voxel SIZE (e.g. --voxel 40um)")
        if a.subsample < 1 or a.subsample > 16:
            raise ExportError("ncf-export: option --subsample: value %d must be in 1..16" % a.subsample)
        # every input read and checked before the first file is written
        outs = [(o, v) for o, v in (("--vtu", a.vtu), ("--vti", a.vti), ("--vtk", a.vtk)) if v]
        for opt, path in outs:
            folder = os.path.dirname(os.path.abspath(path))
            if os.path.isdir(path):
                raise ExportError("ncf-export: option %s: '%s' is a folder, not a file name" % (opt, path))
            if not os.path.isdir(folder):
                raise ExportError("ncf-export: option %s: the folder of '%s' does not exist" % (opt, path))
            if not os.access(folder, os.W_OK):
                raise ExportError("ncf-export: option %s: cannot write in the folder of '%s'" % (opt, path))
        if len(set(os.path.abspath(p) for _, p in outs)) != len(outs):
            raise ExportError("ncf-export: the same file is given to two of --vtu, --vti, --vtk")
        kinds, nlayers = read_summary(a.summary)
        d = read_data(a.data)
        # the summary of another fabric: its diameters and packings would be exported silently.
        # The fabric's box, or (a box deformed by a virtual test) its number of nodes
        try:
            ncf_measure.check_box(d, ncf_measure.read_summary(a.summary), a.data)
        except ncf_measure.MeasureError as e:
            total = summary_atoms(a.summary)
            n = len(d.ids) + (len(read_data(a.yarn).ids) if a.yarn else 0)
            if total is None or n != total:
                raise ExportError("ncf-export: %s; and its %d nodes are not the summary's %s either"
                                  % (e, n, total if total is not None else "(unknown)"))
        if a.yarn:
            append(d, read_data(a.yarn))
        if len(d.bonds) == 0:
            raise ExportError("ncf-export: %s: no bonds: nothing to export" % a.data)
        h, zr = None, None
        if a.vti or a.vtk:
            h = length(a.voxel, "--voxel")
            box = min(d.hi[0] - d.lo[0], d.hi[1] - d.lo[1])
            if h > box:
                raise ExportError("ncf-export: option --voxel: value %s is larger than the box (%.4g mm)"
                                  % (a.voxel, box * 1e3))
            if a.z_range:
                w = a.z_range.split(",")
                if len(w) != 2:
                    raise ExportError("ncf-export: option --z-range: value '%s': expected ZLO,ZHI" % a.z_range)
                zr = tuple(length(x, "--z-range", signed=True) for x in w)
                if zr[1] <= zr[0]:
                    raise ExportError("ncf-export: option --z-range: value '%s' is empty" % a.z_range)
        if a.vtu:
            write_vtu(d, kinds, a.vtu, a.quiet)
        if a.vti or a.vtk:
            write_vti(d, kinds, nlayers, h, a.subsample, a.vti, a.vtk, zr, a.quiet)
    except ExportError as e:
        print(str(e), file=sys.stderr)
        return 1
    except (OSError, ValueError, IndexError, KeyError, MemoryError) as e:
        # (a file that cannot be written, a grid too large for the memory: said, no traceback)
        print("ncf-export: %s" % ncf_measure.describe_error(e), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
