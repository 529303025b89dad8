#!/usr/bin/python3
"""ncf-perm: the permeability tensor of a periodic voxel grid (VTK ImageData with a cell array vf).

This front-end reads the grid with VTK (Debian's python3-vtk9: .vti in any encoding VTK and
ParaView write, ASCII, base64 binary, appended raw or base64, compressed or not; legacy .vtk
STRUCTURED_POINTS), checks it, hands vf (and dir) to the FFTW solver ncf-perm-solve (C++) and
passes its output through: iterations, residual, symmetry error, and the tensor as the last three
lines. With --flux-out the velocity fields of the three loads are written back into a copy of the
grid. doc/ncf_perm.md.
"""

import argparse
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

# the argument types of ncf-measure (tools/ncf-measure/ncf_measure.py, beside this tool)
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "ncf-measure"))
from ncf_measure import finite_arg, int_arg  # noqa: E402


class PermError(Exception):
    pass


def _vtk():
    try:
        import vtk
        from vtk.util import numpy_support
    except ImportError as e:
        raise PermError("ncf-perm: the Python VTK module is missing (Debian package python3-vtk9): %s" % e)
    return vtk, numpy_support


def read_grid(path):
    """(image, dims of the cells, spacing, arrays by name as numpy, where ('cell'|'point'))."""
    vtk, ns = _vtk()
    if not os.path.isfile(path):
        raise PermError("ncf-perm: grid file '%s' does not exist" % path)
    ext = os.path.splitext(path)[1].lower()
    if ext == ".vti":
        rd = vtk.vtkXMLImageDataReader()
        if not rd.CanReadFile(path):
            raise PermError("ncf-perm: '%s' is not a VTK XML ImageData file (.vti)" % path)
    elif ext == ".vtk":
        rd = vtk.vtkStructuredPointsReader()
        rd.SetFileName(path)
        if not rd.IsFileStructuredPoints():
            raise PermError("ncf-perm: '%s' is not a legacy VTK STRUCTURED_POINTS file" % path)
    else:
        raise PermError("ncf-perm: grid file '%s': expected .vti (VTK XML ImageData) or .vtk "
                        "(legacy STRUCTURED_POINTS)" % path)
    rd.SetFileName(path)
    rd.Update()
    img = rd.GetOutput()
    if img is None or img.GetNumberOfPoints() == 0:
        raise PermError("ncf-perm: '%s': VTK read no grid from it" % path)
    return img


def grid_arrays(img, path):
    """vf (and dir) as cell arrays on one period: (n, h, vf, dir or None, where)."""
    vtk, ns = _vtk()
    dims = list(img.GetDimensions())    # points
    h = list(img.GetSpacing())
    cd, pd = img.GetCellData(), img.GetPointData()
    if cd.GetArray("vf") is not None:
        where = "cell"
        n = [max(d - 1, 1) for d in dims]
        vf = ns.vtk_to_numpy(cd.GetArray("vf")).astype(float)
        darr = cd.GetArray("dir")
        dr = ns.vtk_to_numpy(darr).astype(float) if darr is not None else None
    elif pd.GetArray("vf") is not None:
        # point data: the grid is one period only if its last plane repeats its first
        where = "point"
        vf = ns.vtk_to_numpy(pd.GetArray("vf")).astype(float).reshape(dims[2], dims[1], dims[0])
        darr = pd.GetArray("dir")
        dr = ns.vtk_to_numpy(darr).astype(float).reshape(dims[2], dims[1], dims[0], 3) \
            if darr is not None else None
        sl = [slice(None)] * 3
        for ax, name in ((2, "x"), (1, "y"), (0, "z")):
            m = vf.shape[ax]
            if m == 1:
                continue
            first = np.take(vf, 0, axis=ax)
            last = np.take(vf, m - 1, axis=ax)
            if not np.allclose(first, last, atol=1e-6):
                raise PermError(
                    "ncf-perm: %s: array 'vf' is point data on %d points along %s whose first "
                    "and last planes differ (largest difference %.3g): not one period of a periodic "
                    "grid (give vf as cell data on the period, or point data with the last plane "
                    "repeating the first)" % (path, m, name, float(np.max(np.abs(first - last)))))
            sl[ax] = slice(0, m - 1)
        vf = vf[tuple(sl)]
        if dr is not None:
            dr = dr[tuple(sl)]
        n = [vf.shape[2], vf.shape[1], vf.shape[0]]
        vf = vf.reshape(-1)
        if dr is not None:
            dr = dr.reshape(-1, 3)
    else:
        names = [cd.GetArrayName(i) for i in range(cd.GetNumberOfArrays())] + \
                [pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays())]
        raise PermError("ncf-perm: %s: no array 'vf' (fibre volume fraction per cell); the grid "
                        "has %s" % (path, ", ".join("'%s'" % s for s in names) if names else "no arrays"))
    if vf.ndim != 1:
        if vf.ndim == 2 and vf.shape[1] == 1:
            vf = vf[:, 0]
        else:
            raise PermError("ncf-perm: %s: array 'vf' has %d components (need 1)" % (path, vf.shape[1]))
    if dr is not None and (dr.ndim != 2 or dr.shape[1] != 3):
        raise PermError("ncf-perm: %s: array 'dir' must have 3 components" % path)
    N = n[0] * n[1] * n[2]
    if vf.size != N:
        raise PermError("ncf-perm: %s: array 'vf' has %d values for %d cells" % (path, vf.size, N))
    bad = ~np.isfinite(vf) | (vf < 0) | (vf > 1)
    if np.any(bad):
        k = int(np.nonzero(bad)[0][0])
        i, j, kk = k % n[0], (k // n[0]) % n[1], k // (n[0] * n[1])
        raise PermError("ncf-perm: %s: array 'vf': value %g at cell (%d,%d,%d) is outside 0..1"
                        % (path, vf[k], i, j, kk))
    for ax, name in enumerate("xyz"):
        if not (h[ax] > 0):
            raise PermError("ncf-perm: %s: spacing along %s is %g (must be > 0)" % (path, name, h[ax]))
    return n, h, vf, dr, where


def field_value(img, name):
    a = img.GetFieldData().GetArray(name) if img.GetFieldData() is not None else None
    if a is None or a.GetNumberOfTuples() < 1:
        return None
    return float(a.GetTuple1(0))


def solver_path():
    p = os.environ.get("NCF_PERM_SOLVER")
    if p and os.access(p, os.X_OK):
        return p
    for d in os.environ.get("PATH", "").split(os.pathsep):
        q = os.path.join(d, "ncf-perm-solve")
        if os.access(q, os.X_OK):
            return q
    raise PermError("ncf-perm: the solver ncf-perm-solve was not found (build the package: "
                    "tools/setup.sh; or set NCF_PERM_SOLVER)")


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        self.print_usage(sys.stderr)
        sys.stderr.write("ncf-perm: error: %s\n" % message)
        sys.exit(2)


def parse_args(argv):
    p = _Parser(prog="ncf-perm", description=__doc__.split("\n")[0])
    p.add_argument("grid", help="VTK ImageData (.vti, or legacy .vtk) with a cell array vf (0..1), "
                               "optional dir (3 components)")
    p.add_argument("--medium", choices=["fibrous", "solid"], default="fibrous",
                   help="fibrous: vf is the fibre volume fraction of filament bundles (Brinkman, "
                        "Gebart); solid: vf is the solid fraction of impermeable bodies")
    p.add_argument("--fibre-radius", type=finite_arg, default=None,
                   help="filament radius [m] for Gebart (default: the grid's field ncf_fibre_radius)")
    p.add_argument("--packing", choices=["hexagonal", "square"], default="hexagonal",
                   help="filament arrangement for Gebart's formulas (default hexagonal)")
    p.add_argument("--solid-vf", type=finite_arg, default=None,
                   help="fibrous: vf at and above which a cell is solid (default Gebart's maximum "
                        "packing, 0.9069 hexagonal, 0.7854 square)")
    p.add_argument("--tol", type=finite_arg, default=1e-6, help="relative residual (default 1e-6)")
    p.add_argument("--max-iter", type=int_arg, default=20000)
    p.add_argument("--penalty", type=finite_arg, default=1e4,
                   help="resistance of solid faces in units of 1/h^2 (default 1e4)")
    p.add_argument("--threads", type=int_arg, default=None,
                   help="threads (default: OMP_NUM_THREADS, else the cores)")
    p.add_argument("--plan", choices=["estimate", "measure"], default="estimate")
    p.add_argument("--loads", default="xyz", help="which mean pressure gradients (default xyz)")
    p.add_argument("--flux-out", default=None,
                   help="write the grid with the velocity fields u_x, u_y, u_z of the loads [m^2 "
                        "per unit gradient and viscosity] to this .vti")
    p.add_argument("-q", "--quiet", action="store_true")
    # ('--tol -1': a value that starts with '-' is taken for an option by argparse)
    out, i = [], 0
    while i < len(argv):
        if argv[i].startswith("--") and "=" not in argv[i] and i + 1 < len(argv) and \
                re.match(r"^-[0-9.]", argv[i + 1]):
            out.append("%s=%s" % (argv[i], argv[i + 1]))
            i += 2
        else:
            out.append(argv[i])
            i += 1
    return p.parse_args(out)


def check_args(a):
    """The options' ranges, before the grid is read or anything written."""
    if a.fibre_radius is not None and not (1e-8 <= a.fibre_radius <= 1e-3):
        raise PermError("ncf-perm: option --fibre-radius: value %g m must be between 0.01 um and "
                        "1 mm (a filament radius in metres: 3.5e-6)" % a.fibre_radius)
    if a.solid_vf is not None and not (0.0 < a.solid_vf <= 1.0):
        raise PermError("ncf-perm: option --solid-vf: value %g must be in (0, 1]" % a.solid_vf)
    if not (0.0 < a.tol < 1.0):
        raise PermError("ncf-perm: option --tol: value %g must be in (0, 1)" % a.tol)
    if a.max_iter < 1:
        raise PermError("ncf-perm: option --max-iter: value %d must be >= 1" % a.max_iter)
    if not (a.penalty > 0.0):
        raise PermError("ncf-perm: option --penalty: value %g must be > 0" % a.penalty)
    if a.threads is not None and not (1 <= a.threads <= 4096):
        raise PermError("ncf-perm: option --threads: value %d must be in 1..4096" % a.threads)
    if not a.loads or any(c not in "xyz" for c in a.loads) or len(set(a.loads)) != len(a.loads):
        raise PermError("ncf-perm: option --loads: value '%s' must be letters of xyz, each once"
                        % a.loads)
    if a.flux_out:
        folder = os.path.dirname(os.path.abspath(a.flux_out))
        if os.path.isdir(a.flux_out) or not os.path.isdir(folder):
            raise PermError("ncf-perm: option --flux-out: cannot write '%s' (a folder, or in a "
                            "folder that does not exist)" % a.flux_out)


def main(argv=None):
    a = parse_args(sys.argv[1:] if argv is None else argv)
    try:
        check_args(a)
        img = read_grid(a.grid)
        n, h, vf, dr, where = grid_arrays(img, a.grid)
        rf = a.fibre_radius if a.fibre_radius is not None else field_value(img, "ncf_fibre_radius")
        if a.fibre_radius is not None and not (a.fibre_radius > 0):
            raise PermError("ncf-perm: option --fibre-radius: value %g must be > 0" % a.fibre_radius)
        solver = solver_path()
        threads = a.threads or int(os.environ.get("OMP_NUM_THREADS", "0") or 0) or os.cpu_count() or 1
        with tempfile.TemporaryDirectory(prefix="ncf-perm-") as tmp:
            raw = os.path.join(tmp, "grid.raw")
            with open(raw, "wb") as f:
                f.write(("NCFPERM 1 %d %d %d %.17g %.17g %.17g %d\n"
                         % (n[0], n[1], n[2], h[0], h[1], h[2], 3 if dr is not None else 0)).encode())
                f.write(np.ascontiguousarray(vf, dtype="<f8").tobytes())
                if dr is not None:
                    f.write(np.ascontiguousarray(dr, dtype="<f8").tobytes())
            cmd = [solver, raw, "--medium", a.medium, "--packing", a.packing, "--tol", repr(a.tol),
                   "--max-iter", str(a.max_iter), "--penalty", repr(a.penalty), "--threads",
                   str(threads), "--plan", a.plan, "--loads", a.loads]
            if rf is not None:
                cmd += ["--fibre-radius", repr(rf)]
            if a.solid_vf is not None:
                cmd += ["--solid-vf", repr(a.solid_vf)]
            fields = os.path.join(tmp, "fields.raw")
            if a.flux_out:
                cmd += ["--fields", fields]
            if a.quiet:
                cmd += ["--quiet"]
            print("ncf-perm: %s: %d x %d x %d cells (%s data), spacing %.6g %.6g %.6g m, medium %s%s"
                  % (a.grid, n[0], n[1], n[2], where, h[0], h[1], h[2], a.medium,
                     ", filament radius %.4g m (%s)" % (rf, "option" if a.fibre_radius else "grid field")
                     if rf else ""))
            sys.stdout.flush()
            # the solver's lines pass through as they come, except the tensor, which stays the last
            # three lines of the output (after the note on the flux file)
            proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, text=True)
            held = []
            for line in proc.stdout:
                if held or line.startswith("ncf-perm: permeability tensor"):
                    held.append(line)
                else:
                    sys.stdout.write(line)
                    sys.stdout.flush()
            rc = proc.wait()
            if rc == 1:
                return 1
            if a.flux_out and os.path.exists(fields):
                write_fluxes(img, n, where, fields, a.flux_out)
            sys.stdout.write("".join(held))
            return rc
    except PermError as e:
        print(str(e), file=sys.stderr)
        return 1
    except (OSError, ValueError, IndexError, KeyError, MemoryError) as e:
        # (a file that cannot be read or written, a grid too large: said, without a traceback)
        name = getattr(e, "filename", None)
        print("ncf-perm: %s%s" % ("%s: " % name if name else "", getattr(e, "strerror", None) or e),
              file=sys.stderr)
        return 1


def write_fluxes(img, n, where, fields, out):
    vtk, ns = _vtk()
    N = n[0] * n[1] * n[2]
    u = np.fromfile(fields, dtype="<f8").reshape(3, 3, N)
    res = vtk.vtkImageData()
    res.SetOrigin(img.GetOrigin())
    res.SetSpacing(img.GetSpacing())
    res.SetDimensions(n[0] + 1, n[1] + 1, n[2] + 1)
    if where == "cell":
        res.DeepCopy(img)    # the grid's own arrays, the velocities beside them
    cd = res.GetCellData()
    for load, name in enumerate("xyz"):
        arr = ns.numpy_to_vtk(np.ascontiguousarray(u[load].T), deep=1)
        arr.SetName("u_" + name)
        cd.AddArray(arr)
    w = vtk.vtkXMLImageDataWriter()
    w.SetFileName(out)
    w.SetInputData(res)
    if not w.Write():
        raise PermError("ncf-perm: option --flux-out: cannot write '%s'" % out)
    print("ncf-perm: velocity fields u_x, u_y, u_z (per unit pressure gradient along x, y, z, "
          "viscosity 1) -> %s" % out)


if __name__ == "__main__":
    sys.exit(main())
