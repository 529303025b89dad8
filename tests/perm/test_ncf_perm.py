#!/usr/bin/python3
"""ncf-perm as a user runs it on grids written by other software (VTK): a square array of
cylinders in every encoding VTK writes gives the same tensor, Sangani-Acrivos' value, point data
with a repeated last plane, the flux fields back in a .vti; bad grids give errors naming the array.
Run by ctest (unit.perm_ncf_perm) with NCF_ROOT and NCF_PERM_SOLVER set."""

import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np
import vtk
from vtk.util import numpy_support as ns

ROOT = os.environ.get("NCF_ROOT", os.path.join(os.path.dirname(__file__), "..", ".."))
SCRIPT = os.path.join(ROOT, "tools", "ncf-perm", "ncf_perm.py")


def cylinders(n, phi, L=1e-3, ss=8, point=False):
    R = np.sqrt(phi / np.pi) * L
    h = L / n
    s = (np.arange(ss) + 0.5) / ss
    x = (np.arange(n)[:, None] + s[None, :]).reshape(-1) * h - L / 2
    X, Y = np.meshgrid(x, x, indexing="xy")
    vf = (X ** 2 + Y ** 2 < R * R).astype(float).reshape(n, ss, n, ss).mean(axis=(1, 3))
    img = vtk.vtkImageData()
    img.SetSpacing(h, h, h)
    if point:
        # the same cells as point data on n+1 points per side, the last plane repeating the first
        v = np.zeros((2, n + 1, n + 1))
        v[:, :n, :n] = vf
        v[:, n, :n] = vf[0]
        v[:, :n, n] = vf[:, 0]
        v[:, n, n] = vf[0, 0]
        img.SetDimensions(n + 1, n + 1, 2)
        a = ns.numpy_to_vtk(v.reshape(-1).copy(), deep=1)
        a.SetName("vf")
        img.GetPointData().AddArray(a)
    else:
        img.SetDimensions(n + 1, n + 1, 2)
        a = ns.numpy_to_vtk(vf.reshape(-1).copy(), deep=1)
        a.SetName("vf")
        img.GetCellData().AddArray(a)
    return img


def write(img, path, mode="appended", compress=True):
    w = vtk.vtkXMLImageDataWriter()
    w.SetFileName(path)
    w.SetInputData(img)
    if mode == "ascii":
        w.SetDataModeToAscii()
    elif mode == "binary":
        w.SetDataModeToBinary()
    elif mode == "appended":
        w.SetDataModeToAppended()
        w.EncodeAppendedDataOff()
    elif mode == "appended64":
        w.SetDataModeToAppended()
        w.EncodeAppendedDataOn()
    if not compress:
        w.SetCompressorTypeToNone()
    assert w.Write()


def run(*args):
    p = subprocess.run([sys.executable, "-B", SCRIPT] + list(args) + ["--threads", "1"],
                       capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


def tensor(out):
    rows = out.strip().splitlines()[-3:]
    return np.array([[float(t) for t in r.split()] for r in rows])


class NcfPerm(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="test-ncf-perm-")
        cls.d = cls.tmp.name

    def path(self, name):
        return os.path.join(self.d, name)

    def test_encodings_same_tensor_and_sangani_acrivos(self):
        img = cylinders(48, 0.3)
        Ks = []
        for mode, comp in (("ascii", True), ("binary", True), ("appended", True),
                           ("appended64", True), ("appended", False), ("binary", False)):
            f = self.path("c_%s_%d.vti" % (mode, comp))
            write(img, f, mode, comp)
            rc, out, err = run(f, "--medium", "solid", "--loads", "xz")
            self.assertEqual(rc, 0, out + err)
            Ks.append(tensor(out))
        for K in Ks[1:]:
            np.testing.assert_allclose(K, Ks[0], rtol=1e-12, atol=1e-25)
        L = 1e-3
        R2 = 0.3 / np.pi * L * L
        self.assertLess(abs(Ks[0][0, 0] / R2 / 0.1018 - 1), 0.02)
        # the parallel permeability, larger than the transverse one
        self.assertGreater(Ks[0][2, 2], 2 * Ks[0][0, 0])
        # a legacy STRUCTURED_POINTS file of the same grid
        w = vtk.vtkStructuredPointsWriter()
        w.SetFileName(self.path("c.vtk"))
        w.SetInputData(img)
        self.assertTrue(w.Write())
        rc, out, err = run(self.path("c.vtk"), "--medium", "solid", "--loads", "xz")
        self.assertEqual(rc, 0, out + err)
        # (the legacy ASCII writer rounds vf to 6 digits)
        np.testing.assert_allclose(tensor(out), Ks[0], rtol=1e-4, atol=1e-6 * Ks[0].max())

    def test_point_data_one_period(self):
        write(cylinders(32, 0.3), self.path("cell.vti"))
        write(cylinders(32, 0.3, point=True), self.path("point.vti"))
        rc1, o1, e1 = run(self.path("cell.vti"), "--medium", "solid", "--loads", "x")
        rc2, o2, e2 = run(self.path("point.vti"), "--medium", "solid", "--loads", "x")
        self.assertEqual(rc1, 0, o1 + e1)
        self.assertEqual(rc2, 0, o2 + e2)
        np.testing.assert_allclose(tensor(o2), tensor(o1), rtol=1e-12, atol=1e-25)

    def test_flux_fields(self):
        write(cylinders(32, 0.3), self.path("f.vti"))
        rc, out, err = run(self.path("f.vti"), "--medium", "solid", "--flux-out", self.path("flux.vti"))
        self.assertEqual(rc, 0, out + err)
        K = tensor(out)
        r = vtk.vtkXMLImageDataReader()
        r.SetFileName(self.path("flux.vti"))
        r.Update()
        cd = r.GetOutput().GetCellData()
        for j, name in enumerate("xyz"):
            u = ns.vtk_to_numpy(cd.GetArray("u_" + name))
            np.testing.assert_allclose(u.mean(axis=0), K[:, j], rtol=1e-6, atol=1e-6 * abs(K).max())
        self.assertIsNotNone(cd.GetArray("vf"))

    def test_bad_grids(self):
        img = cylinders(8, 0.3)
        # no vf
        other = vtk.vtkImageData()
        other.DeepCopy(img)
        other.GetCellData().GetArray("vf").SetName("porosity")
        write(other, self.path("novf.vti"))
        rc, out, err = run(self.path("novf.vti"))
        self.assertEqual(rc, 1)
        self.assertIn("no array 'vf'", err)
        self.assertIn("'porosity'", err)
        # vf outside 0..1
        bad = vtk.vtkImageData()
        bad.DeepCopy(img)
        bad.GetCellData().GetArray("vf").SetValue(10, 1.5)
        write(bad, self.path("range.vti"))
        rc, out, err = run(self.path("range.vti"), "--medium", "solid")
        self.assertEqual(rc, 1)
        self.assertIn("'vf': value 1.5 at cell (2,1,0) is outside 0..1", err)
        # fully solid
        full = vtk.vtkImageData()
        full.DeepCopy(img)
        full.GetCellData().GetArray("vf").Fill(1.0)
        write(full, self.path("solid.vti"))
        rc, out, err = run(self.path("solid.vti"))
        self.assertEqual(rc, 1)
        self.assertIn("every cell is solid", err)
        # point data that is not one period (the last plane does not repeat the first)
        pimg = cylinders(8, 0.3, point=True)
        arr = pimg.GetPointData().GetArray("vf")
        for k in range(arr.GetNumberOfTuples()):
            arr.SetValue(k, (k % 9) / 8.0)
        write(pimg, self.path("nonper.vti"))
        rc, out, err = run(self.path("nonper.vti"), "--medium", "solid")
        self.assertEqual(rc, 1)
        self.assertIn("not one period", err)
        # fibre bundles without a filament radius
        fib = vtk.vtkImageData()
        fib.DeepCopy(img)
        fib.GetCellData().GetArray("vf").Fill(0.3)
        write(fib, self.path("fib.vti"))
        rc, out, err = run(self.path("fib.vti"))
        self.assertEqual(rc, 1)
        self.assertIn("--fibre-radius", err)
        rc, out, err = run(self.path("fib.vti"), "--fibre-radius", "-1")
        self.assertEqual(rc, 1)
        self.assertIn("--fibre-radius: value -1", err)
        rc, out, err = run(self.path("missing.vti"))
        self.assertEqual(rc, 1)
        self.assertIn("does not exist", err)


if __name__ == "__main__":
    unittest.main(verbosity=2)
