#!/usr/bin/python3
"""ncf-export round trips through Debian's python3-vtk9 and python3-meshio, on a synthetic fabric
with known answers: chains along x (one crossing the periodic x face by a bond, one through the y
face), a chain along y, a stitching-yarn loop closed through the x face; data files in atom_style
bond and angle, with and without the style hint. Run by ctest (unit.perm_ncf_export)."""

import math
import os
import subprocess
import sys
import tempfile
import unittest

import meshio
import numpy as np
import vtk
from vtk.util import numpy_support as ns

ROOT = os.environ.get("NCF_ROOT", os.path.join(os.path.dirname(__file__), "..", ".."))
SCRIPT = os.path.join(ROOT, "tools", "ncf-export", "ncf_export.py")
sys.path.insert(0, os.path.dirname(SCRIPT))
import ncf_export  # noqa: E402

LX, LY = 1.0e-3, 0.8e-3
D, DY, PACK, PACKY = 69e-6, 80e-6, 0.5, 0.9
SUMMARY = """ncf-gen summary of 'synthetic'

layer 1 (atom/bond type 1)
  nominal angle, sigma                0 deg, 0 deg
  chain d_c, packing                  69 um, 0.5
  filaments per chain                 48.58

layer 2 (atom/bond type 2)
  nominal angle, sigma                90 deg, 0 deg
  chain d_c, packing                  69 um, 0.5
  filaments per chain                 48.58

stitching yarn (atom/bond type 3)
  material                            PES
  chain diameter, packing             80 um, 0.9
"""


def scene():
    """atoms (id, mol, type, x, y, z) and bonds (type, a, b): every chain well apart."""
    atoms, bonds = [], []

    def chain(mol, typ, pts, closed=False):
        first = len(atoms) + 1
        for p in pts:
            atoms.append((len(atoms) + 1, mol, typ) + tuple(p))
        last = len(atoms)
        for k in range(first, last):
            bonds.append((typ, k, k + 1))
        if closed:
            bonds.append((typ, last, first))

    # layer 1, along x at y = 0.2 mm, z = 0.1 mm: 5 nodes 0.2 mm apart, wrapped positions, the
    # bond from the last node to the first closes the chain through the x face
    chain(1, 1, [((0.1e-3 + 0.2e-3 * k) % LX, 0.2e-3, 0.1e-3) for k in range(5)], closed=True)
    # layer 1, a straight oblique chain that leaves through the y face (open chain)
    chain(2, 1, [(0.15e-3 + 0.2e-3 * k, (0.6e-3 + 0.1e-3 * k) % LY, 0.25e-3) for k in range(4)])
    # layer 2, along y at x = 0.5 mm, z = 0.4 mm, closed through the y face
    chain(3, 2, [(0.5e-3, (0.05e-3 + 0.2e-3 * k) % LY, 0.4e-3) for k in range(4)], closed=True)
    # the yarn: a loop along x at y = 0.6 mm, z = 0.55 mm, closed through the x face
    chain(4, 3, [((0.05e-3 + 0.25e-3 * k) % LX, 0.6e-3, 0.55e-3) for k in range(4)], closed=True)
    return atoms, bonds


def write_data(path, style, hint=True, images=True):
    atoms, bonds = scene()
    with open(path, "w") as f:
        f.write("LAMMPS data file: synthetic\n\n%d atoms\n3 atom types\n%d bonds\n3 bond types\n"
                % (len(atoms), len(bonds)))
        if style == "angle":
            f.write("0 angles\n1 angle types\n")
        f.write("\n0 %r xlo xhi\n0 %r ylo yhi\n-0.001 0.002 zlo zhi\n\nMasses\n\n1 1\n2 1\n3 1\n\n"
                % (LX, LY))
        f.write("Atoms%s\n\n" % ((" # " + style) if hint else ""))
        for a in atoms:
            f.write("%d %d %d %.17g %.17g %.17g%s\n" % (a + (" 0 0 0" if images else "",)))
        f.write("\nBonds\n\n")
        for k, b in enumerate(bonds, 1):
            f.write("%d %d %d %d\n" % ((k,) + b))
        if style == "angle":
            f.write("\nAngles\n\n")
        f.write("\nNCF_NODE\n\n")
        for a in atoms:
            f.write("%d %d 0\n" % (a[0], 0 if a[2] == 3 else a[2]))


def exact_bond_lengths():
    atoms, bonds = scene()
    P = {a[0]: np.array(a[3:6]) for a in atoms}
    out = []
    for _, a, b in bonds:
        v = P[b] - P[a]
        v[0] -= LX * round(v[0] / LX)
        v[1] -= LY * round(v[1] / LY)
        out.append(np.linalg.norm(v))
    return np.array(out), bonds, atoms


def chains_volume():
    L, bonds, atoms = exact_bond_lengths()
    r = {1: D / 2, 2: D / 2, 3: DY / 2}
    p = {1: PACK, 2: PACK, 3: PACKY}
    return sum(l * math.pi * r[b[0]] ** 2 * p[b[0]] for l, b in zip(L, bonds))


class NcfExport(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="test-ncf-export-")
        cls.d = cls.tmp.name
        with open(os.path.join(cls.d, "s.summary"), "w") as f:
            f.write(SUMMARY)

    def path(self, n):
        return os.path.join(self.d, n)

    def export(self, data, *args):
        p = subprocess.run([sys.executable, "-B", SCRIPT, data, "--summary", self.path("s.summary")]
                           + list(args), capture_output=True, text=True)
        return p.returncode, p.stdout, p.stderr

    def test_vtu_round_trip(self):
        L, bonds, atoms = exact_bond_lengths()
        for style, hint, images in (("bond", True, True), ("angle", True, True), ("bond", False, False),
                                    ("angle", False, True)):
            data = self.path("s_%s_%d_%d.data" % (style, hint, images))
            write_data(data, style, hint, images)
            out = self.path("s_%s_%d.vtu" % (style, hint))
            rc, o, e = self.export(data, "--vtu", out)
            self.assertEqual(rc, 0, o + e)
            r = vtk.vtkXMLUnstructuredGridReader()
            r.SetFileName(out)
            r.Update()
            ug = r.GetOutput()
            self.assertEqual(ug.GetNumberOfCells(), len(bonds))
            P = ns.vtk_to_numpy(ug.GetPoints().GetData())
            conn = ns.vtk_to_numpy(ug.GetCells().GetConnectivityArray()).reshape(-1, 2)
            self.assertTrue(all(ug.GetCellType(k) == vtk.VTK_LINE for k in range(ug.GetNumberOfCells())))
            lengths = np.linalg.norm(P[conn[:, 1]] - P[conn[:, 0]], axis=1)
            np.testing.assert_allclose(lengths, L, rtol=1e-12)
            # continuity: an open chain's consecutive bonds share their points (no jump at a face)
            pd = ug.GetPointData()
            chain = ns.vtk_to_numpy(pd.GetArray("chain"))
            layer = ns.vtk_to_numpy(pd.GetArray("layer"))
            yarn = ns.vtk_to_numpy(pd.GetArray("yarn"))
            radius = ns.vtk_to_numpy(pd.GetArray("radius"))
            tang = ns.vtk_to_numpy(pd.GetArray("tangent"))
            two = np.nonzero(chain[conn[:, 0]] == 2)[0]
            self.assertEqual(len(two), 3)
            for k in range(len(two) - 1):
                self.assertEqual(conn[two[k], 1], conn[two[k + 1], 0])
            # the closed chains: one extra point each where the loop closes through a face
            self.assertEqual(len(P), len(atoms) + 3)
            self.assertEqual(set(layer[yarn == 1]), {0})
            np.testing.assert_allclose(radius[yarn == 1], DY / 2)
            np.testing.assert_allclose(radius[yarn == 0], D / 2)
            np.testing.assert_allclose(np.abs(tang[chain == 1][:, 0]), 1.0, atol=1e-12)
            np.testing.assert_allclose(np.abs(tang[chain == 3][:, 1]), 1.0, atol=1e-12)
            # meshio reads the same lines
            m = meshio.read(out)
            self.assertEqual(sum(len(c.data) for c in m.cells if c.type == "line"), len(bonds))
            np.testing.assert_allclose(m.points, P)

    def test_vti_volume_phase_direction(self):
        data = self.path("v.data")
        write_data(data, "angle")
        vti, leg = self.path("v.vti"), self.path("v.vtk")
        h = 10e-6
        # the total fibre volume with the default sub-sampling (4 x 4 x 4 points per voxel), at a
        # voxel size not commensurate with the chain positions
        rc, o, e = self.export(data, "--vti", self.path("v13.vti"), "--voxel", "13um",
                               "--z-range=-0.1mm,0.7mm")
        self.assertEqual(rc, 0, o + e)
        r = vtk.vtkXMLImageDataReader()
        r.SetFileName(self.path("v13.vti"))
        r.Update()
        sp = r.GetOutput().GetSpacing()
        vf = ns.vtk_to_numpy(r.GetOutput().GetCellData().GetArray("vf"))
        self.assertLess(abs(vf.sum() * sp[0] * sp[1] * sp[2] / chains_volume() - 1), 0.01)
        # 10 um voxels, aligned with the chains' axes (the sub-points then sample each circle on a
        # lattice: 1.06 % off at 4 per edge, doc/ncf_export.md), with 8 per edge
        rc, o, e = self.export(data, "--vti", vti, "--vtk", leg, "--voxel", "10um",
                               "--z-range=-0.1mm,0.7mm", "--subsample", "8")
        self.assertEqual(rc, 0, o + e)
        r = vtk.vtkXMLImageDataReader()
        r.SetFileName(vti)
        r.Update()
        img = r.GetOutput()
        n = [d - 1 for d in img.GetDimensions()]
        sp = img.GetSpacing()
        self.assertEqual(n, [100, 80, 80])
        np.testing.assert_allclose(sp, [h, h, h], rtol=1e-12)
        cd = img.GetCellData()
        vf = ns.vtk_to_numpy(cd.GetArray("vf"))
        vol = vf.sum() * sp[0] * sp[1] * sp[2]
        exact = chains_volume()
        self.assertLess(abs(vol / exact - 1), 0.01)
        # the cell at the centre of chain 1's axis (x = 0.3 mm, y = 0.2 mm, z = 0.1 mm): inside
        # the cylinder, vf = packing, phase = layer 1, dir = x; the same in the yarn (packing 0.9)
        def cell(x, y, z):
            i, j, k = int(x / h), int(y / h), int((z + 0.1e-3) / h)
            return i + n[0] * (j + n[1] * k)
        dr = ns.vtk_to_numpy(cd.GetArray("dir"))
        ph = ns.vtk_to_numpy(cd.GetArray("phase"))
        a2 = ns.vtk_to_numpy(cd.GetArray("a2"))
        c = cell(0.305e-3, 0.205e-3, 0.105e-3)
        self.assertAlmostEqual(vf[c], PACK, places=12)
        self.assertEqual(ph[c], 1)
        np.testing.assert_allclose(np.abs(dr[c]), [1, 0, 0], atol=1e-12)
        np.testing.assert_allclose(a2[c], [1, 0, 0, 0, 0, 0], atol=1e-12)
        c = cell(0.505e-3, 0.305e-3, 0.405e-3)    # layer 2 along y
        self.assertEqual(ph[c], 2)
        np.testing.assert_allclose(np.abs(dr[c]), [0, 1, 0], atol=1e-12)
        c = cell(0.005e-3, 0.605e-3, 0.555e-3)    # the yarn at the x face (periodic)
        self.assertAlmostEqual(vf[c], PACKY, places=12)
        self.assertEqual(ph[c], 3)
        c = cell(0.905e-3, 0.505e-3, 0.0)          # void
        self.assertEqual(vf[c], 0.0)
        self.assertEqual(ph[c], 0)
        # periodic across the x face: chain 1 covers the cells at both faces alike
        k1 = [cell(x, 0.205e-3, 0.105e-3) for x in (0.005e-3, 0.995e-3)]
        self.assertAlmostEqual(vf[k1[0]], vf[k1[1]], places=12)
        # the legacy file through meshio: the same volume fractions
        m = meshio.read(leg)
        mv = np.concatenate([np.asarray(v).reshape(-1) for v in m.cell_data["vf"]])
        self.assertEqual(len(mv), n[0] * n[1] * n[2])
        self.assertAlmostEqual(float(mv.sum()), float(vf.sum()), places=6)
        # and ncf-export's own reference: the chains' volume x packing from the data file
        k, nl = ncf_export.read_summary(self.path("s.summary"))
        self.assertAlmostEqual(ncf_export.chain_volume(ncf_export.read_data(data), k) / exact, 1.0, places=12)

    def test_bad_input(self):
        data = self.path("b.data")
        write_data(data, "bond")
        rc, o, e = self.export(data, "--vti", self.path("b.vti"))
        self.assertEqual(rc, 1)
        self.assertIn("needs --voxel", e)
        rc, o, e = self.export(data, "--vti", self.path("b.vti"), "--voxel=-3um")
        self.assertEqual(rc, 1)
        self.assertIn("option --voxel: value '-3um'", e)
        rc, o, e = self.export(data, "--vti", self.path("b.vti"), "--voxel", "5mm")
        self.assertEqual(rc, 1)
        self.assertIn("larger than the box", e)
        with open(self.path("full.data"), "w") as f:
            f.write(open(data).read().replace("Atoms # bond", "Atoms # full"))
        rc, o, e = self.export(self.path("full.data"), "--vtu", self.path("b.vtu"))
        self.assertEqual(rc, 1)
        self.assertIn("'Atoms # full'", e)
        rc, o, e = self.export(data)
        self.assertEqual(rc, 1)
        self.assertIn("nothing to write", e)

    def test_summary_of_another_fabric(self):
        # the summary's RVE against the data file's box, or (a box deformed by a virtual test,
        # e.g. the shear's picture frame) its number of nodes
        data = self.path("f.data")
        write_data(data, "bond")
        n = len(scene()[0])

        def summary(name, size, total):
            with open(self.path(name), "w") as f:
                f.write(SUMMARY.replace("\nlayer 1", "\nRVE\n  size Lx (machine) x Ly (gauge)  %s mm\n"
                                        "  total atoms, bonds                  %d, 10\n\nlayer 1"
                                        % (size, total), 1))
            return self.path(name)

        for name, size, total, ok in (("same.summary", "1.0 x 0.8", n, True),
                                      ("sheared.summary", "1.2 x 0.7", n, True),
                                      ("other.summary", "2.0 x 0.8", n + 5, False)):
            p = subprocess.run([sys.executable, "-B", SCRIPT, data, "--summary", summary(name, size, total),
                                "--vtu", self.path(name + ".vtu")], capture_output=True, text=True)
            if ok:
                self.assertEqual(p.returncode, 0, name + ": " + p.stderr)
            else:
                self.assertEqual(p.returncode, 1, name)
                self.assertIn("describes an RVE of 2 x 0.8 mm: the summary of another fabric?", p.stderr)
                self.assertIn("and its %d nodes are not the summary's %d either" % (n, n + 5), p.stderr)
                self.assertFalse(os.path.exists(self.path(name + ".vtu")), "nothing written")


if __name__ == "__main__":
    unittest.main(verbosity=2)
