#!/usr/bin/env python3
"""The checks of examples/virtual-tests/test.sh on the outputs it leaves in OUT (see there).
Prints every measured value; exits 1 when a check fails."""
import math
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import report_virtual_tests as rv  # noqa: E402

out = sys.argv[1]
os.chdir(out)
s = rv.settings("small.settings.lmp")
lx0, ly0 = s["ncf_Lx"], s["ncf_Ly"]
failures = []


def check(ok, what):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok:
        failures.append(what)


def shear_plan(name, logname):
    """The shear's start step (NAME.start.lmp), frame, angle [deg], segments and steps per
    segment (the SHEAR_START line of LOGNAME.log)."""
    with open(f"{name}.start.lmp") as f:
        s0 = int(float(f.read().split()[-1]))
    with open(f"{logname}.log") as f:
        txt = f.read()
    m = re.search(r"SHEAR_START frame (\w+) angle (\S+) deg in (\d+) segments of (\d+) steps", txt)
    if not m:
        sys.exit(f"check_virtual_tests.py: no SHEAR_START line in {logname}.log")
    return s0, m.group(1), float(m.group(2)), int(m.group(3)), int(m.group(4))


def box_of(frame, th):
    if frame == "bias":
        return (lx0 * math.sqrt(2) * math.cos(math.pi / 4 - th / 2),
                ly0 * math.sqrt(2) * math.sin(math.pi / 4 - th / 2), 0.0)
    return lx0, ly0 * math.cos(th), ly0 * math.sin(th)


def kinematics(name, logname=None):
    s0, frame, angle, nseg, nstep = shear_plan(name, logname)
    a = rv.table(f"{name}.dat", 17)
    err = 0.0
    for row in a:
        # the record of step n holds the box of the forces of step n: fix deform's value for
        # step n - 1 (it sets the box of the next step at the end of each step)
        t = (row[0] - 1 - s0) / nstep    # segments done, fractional
        k = min(max(int(math.ceil(t)), 1), nseg)
        f = t - (k - 1)
        b0 = box_of(frame, math.radians(angle * (k - 1) / nseg))
        b1 = box_of(frame, math.radians(angle * k / nseg))
        want = [b0[i] + f * (b1[i] - b0[i]) for i in range(3)]
        got = row[1:4]
        err = max(err, max(abs(g - w) for g, w in zip(got, want)) / lx0)
    pbc = float(a[:, 16].max())
    check(err < 1e-10, f"{name}: box = prescribed picture-frame kinematics ({frame}, {angle:g} deg), "
          f"largest difference {err:.2g} of the box (records at 12 digits)")
    check(pbc < 1e-14, f"{name}: averaged PBC violation at most {pbc:.2g} m")
    return a


def curve(name):
    """w(theta) etc. of a shear record (report_virtual_tests.shear reads PREFIX.shear-SENSE.dat:
    read NAME.dat through a temporary name)."""
    a = rv.table(f"{name}.dat", 17)
    tmp = "_chk.shear-x.dat"
    np.savetxt(tmp, a)
    r = rv.shear(".", "_chk", "x", s)
    os.remove(tmp)
    return r


# ---- kinematics and the averaged PBC: both frames, both senses, cut and on 2 ranks
for name, log in (("small.shear-pos", "small.shear-pos"), ("small.shear-neg", "small.shear-neg"),
                  ("sq", "sq"), ("sqcut", "sqcut1"), ("np2", "np2")):
    kinematics(name, log)

# ---- energy: the work of the box against the stored energy
for name in ("small.shear-pos", "small.shear-neg", "sq"):
    r = curve(name)
    a = rv.table(f"{name}.dat", 17)
    A0 = lx0 * ly0
    work = r["w"][-1] * A0
    stored = (a[-1, 10] - a[0, 10]) + (a[-1, 11] - a[0, 11])
    print(f"      {name}: work of the box {work:.4g} J, stored (pe + ke from the first record) {stored:.4g} J")
    check(work > 0 and work >= stored - 0.05 * abs(work),
          f"{name}: the box's work {work:.4g} J covers the energy stored {stored:.4g} J (dissipation >= 0)")

# ---- restart: the square-frame shear cut into pieces against the uncut one
u, c = rv.table("sq.dat", 17), rv.table("sqcut.dat", 17)
common = np.intersect1d(u[:, 0], c[:, 0])
check(len(common) == len(u), f"restart: the cut shear has every record of the uncut one ({len(common)} of {len(u)})")
ui = np.searchsorted(u[:, 0], common)
ci = np.searchsorted(c[:, 0], common)
scale = np.abs(u[:, 4:10]).max()
d = float(np.abs(u[ui, 4:10] - c[ci, 4:10]).max() / scale)
dy = float(np.abs(u[ui, 12] - c[ci, 12]).max() / max(abs(u[:, 12]).max(), 1e-300))
check(d < 1e-6 and dy < 1e-6,
      f"restart: the virial of the cut shear equals the uncut one's to {d:.2g} of its largest value, "
      f"the yarn tension to {dy:.2g}")

# ---- ranks: 2 ranks against 1 (run.sh's + sense, the same arguments)
u, c = rv.table("small.shear-pos.dat", 17), rv.table("np2.dat", 17)
n = min(len(u), len(c))
check(np.array_equal(u[:n, 0], c[:n, 0]) and len(u) == len(c), "ranks: the same records on 1 and 2 ranks")
d = float(np.abs(u[:n, 4:10] - c[:n, 4:10]).max() / np.abs(u[:, 4:10]).max())
check(d < 1e-6, f"ranks: the virial on 2 ranks equals 1 rank's to {d:.2g} of its largest value")

# ---- friction: the fabric (mu 0.3) against the same fabric with friction switched off for the
# test (chains and plates). Measured: both lose most of the loading work (hysteresis 0.68 with
# friction, 0.73 without; 0.46 without at a five times slower plate): chains without bending
# stiffness rearrange by snap-through (kinetic bursts up to 0.11 of the work without friction) and
# keep a permanent set, so a frictionless mat of digital chains is not elastic
# (doc/howto_virtual_tests.md). What friction does in the model: it holds the mat against the
# plate and the yarn's pull - without it the fabric compacts further at the same pressure and the
# stitch loses its tension.
r = {}
for name, rec in (("mu 0.3", "small.compaction.dat"), ("mu 0", "mu0.dat")):
    a = rv.table(rec, 12)
    if a is None:
        sys.exit(f"check_virtual_tests.py: no {rec}")
    tmp = "_chk.compaction.dat"
    np.savetxt(tmp, a)
    r[name] = rv.compaction(".", "_chk", s)
    os.remove(tmp)
    c = r[name]
    c["vf_turn"] = float(c["vf"][c["load"]][np.argmax(c["p"][c["load"]])])
    c["yarn_end"] = float(c["yarn"][-1])
    print(f"      compaction with {name}: largest pressure {c['pmax']:.4g} Pa at V_f {c['vf_turn']:.4f}, "
          f"loading work {c['w_load']:.4g} J/m^2, unloading {c['w_unload']:.4g} J/m^2, hysteresis "
          f"{c['hysteresis']:.3f}, largest KE / work {c['ke_over_work']:.3g}, yarn tension at the "
          f"start {c['yarn_start']:.4g} N, at the end {c['yarn_end']:.4g} N")
check(r["mu 0"]["vf_turn"] > r["mu 0.3"]["vf_turn"] + 0.01,
      f"friction: without it the mat compacts further at the largest pressure (V_f {r['mu 0']['vf_turn']:.4f} "
      f"against {r['mu 0.3']['vf_turn']:.4f})")
check(r["mu 0"]["yarn_end"] < 0.5 * r["mu 0.3"]["yarn_end"],
      f"friction: without it the stitch loses its tension in the cycle ({r['mu 0']['yarn_end']:.3g} N "
      f"against {r['mu 0.3']['yarn_end']:.3g} N)")

# ---- the stitch makes the asymmetry (the square RVE of straight chains)
sq = rv.settings("square.settings.lmp")


def w_end(name):
    a = rv.table(f"{name}.dat", 17)
    tmp = "_chk.shear-x.dat"
    np.savetxt(tmp, a)
    r = rv.shear(".", "_chk", "x", sq)
    os.remove(tmp)
    return float(r["w"][-1])


asym = {}
for y in ("keep", "delete"):
    wp, wn = w_end(f"square-{y}6"), w_end(f"square-{y}-6")
    asym[y] = (wp - wn) / (0.5 * (wp + wn))
    print(f"      square RVE, yarn {y}: work per area at 6 deg {wp:.4g} (+) / {wn:.4g} (-) J/m^2, "
          f"asymmetry (w+ - w-)/mean {asym[y]:+.3f}")
check(asym["keep"] > 0 and asym["keep"] > 3 * abs(asym["delete"]),
      f"stitch: with the yarn the + sense (stitch stretched) is the stiffer ({asym['keep']:+.3f}), more "
      f"than three times the layers' own asymmetry ({asym['delete']:+.3f})")

if failures:
    print(f"{len(failures)} check(s) failed")
    sys.exit(1)
print("all checks passed")
