#!/usr/bin/python3
"""Writes the scenes of the force-style harness tests (tests/harness): data.ncf-chains (SI units,
for pair_style ncf/contact) and the same chains in micrometres, data.ncf-chains-micro with their
reference lengths ncf-chains-micro-l0.lmp (units micro, for bond_style ncf/chain: the harness
checks the bond forces against finite differences of a fixed step of 6e-6 length units, which in
metres would be 6 % of an element). Run once from this folder (python3 -B make_scene.py); the
files are committed.

Four chains of 69 um and 88 um filaments, 0.1 mm elements:
  chain 1 (type 1) along x, 6 nodes;
  chain 2 (type 1) along y across chain 1, kinked down at the crossing (segment contacts and a
    node cap);
  chain 3 (type 2, 88 um) parallel to chain 1 at 0.9 contact distances (a line contact), also
    under chain 2;
  chain 4 (type 1) along y, 3 nodes, whose free end stops short of chain 1: only its end cap
    (the segment extended by half a diameter) reaches chain 1.
Every node is moved by a few um at random (fixed seed) so that no force vanishes by symmetry,
and carries a random velocity of up to 1 m/s (friction and dashpots act from the first steps).
The per-bond reference lengths L0 (for bond_style ncf/chain) are the initial lengths times a
random factor in [0.995, 1.005]; they are set by `set atom` commands (ncf-chains-micro-l0.lmp) rather
than an NCF_CHAIN_L0 data-file section, because the harness writes its data files with `nofix`,
which leaves fix sections out.
"""
import math
import random

rng = random.Random(20261125)
D1, D2 = 69e-6, 88e-6
L = 1e-4


def jitter(p, a=3e-6):
    return [c + rng.uniform(-a, a) for c in p]


chains = []  # (atom type, bond type, [positions])
chains.append((1, 1, [jitter([i * L, 0.0, 0.0]) for i in range(6)]))
z2 = 0.9 * D1
c2 = []
for k, y in enumerate([-2e-4, -1e-4, 0.0, 1e-4, 2e-4]):
    z = z2 if k == 2 else z2 + 2.0e-5
    c2.append(jitter([2.3e-4, y, z]))
chains.append((1, 1, c2))
d13 = 0.5 * (D1 + D2)
chains.append((2, 2, [jitter([(1 + i) * L, 0.9 * d13, 0.0]) for i in range(4)]))
# free end at y = -0.2 D1 (the contact distance is D1, the end cap reaches 0.5 D1 beyond)
chains.append((1, 1, [jitter([4.6e-4, -0.2 * D1 - (2 - i) * L, 0.85 * D1], 1e-6) for i in range(3)]))

atoms, bonds, vel = [], [], []
for mol, (atype, btype, pts) in enumerate(chains, start=1):
    first = len(atoms) + 1
    for p in pts:
        atoms.append((mol, atype, p))
        vel.append([rng.uniform(-1.0, 1.0) for _ in range(3)])
    for k in range(len(pts) - 1):
        bonds.append((btype, first + k, first + k + 1))

lo = [-3e-4, -4e-4, -2e-4]
hi = [8e-4, 4e-4, 3e-4]
mass = {1: 7e-10, 2: 1.1e-9}

l0 = []
for t, a, b in bonds:
    l0.append(math.dist(atoms[a - 1][2], atoms[b - 1][2]) * rng.uniform(0.995, 1.005))


def write(suffix, length, mass_unit):
    """length, mass_unit: one metre and one kilogram in the units of the file"""
    with open(f"data.ncf-chains{suffix}", "w") as f:
        f.write("USER-NCF harness scene: four chains, crossings, a line contact, a kink, a free end "
                f"(tests/harness/make_scene.py; {'micro' if suffix else 'si'} units)\n\n")
        f.write(f"{len(atoms)} atoms\n{len(bonds)} bonds\n2 atom types\n2 bond types\n\n")
        for d, a in enumerate("xyz"):
            f.write(f"{lo[d] * length!r} {hi[d] * length!r} {a}lo {a}hi\n")
        f.write("\nMasses\n\n")
        for t, m in mass.items():
            f.write(f"{t} {m * mass_unit!r}\n")
        f.write("\nAtoms # bond\n\n")
        for i, (mol, t, p) in enumerate(atoms, start=1):
            f.write(f"{i} {mol} {t} {p[0] * length!r} {p[1] * length!r} {p[2] * length!r}\n")
        # (m/s = um/us)
        f.write("\nVelocities\n\n")
        for i, v in enumerate(vel, start=1):
            f.write(f"{i} {v[0]!r} {v[1]!r} {v[2]!r}\n")
        f.write("\nBonds\n\n")
        for n, (t, a, b) in enumerate(bonds, start=1):
            f.write(f"{n} {t} {a} {b}\n")
    if not suffix:
        return
    # per-bond L0 in the slots of fix NCF_CHAIN_L0: both atoms of a bond carry it (slot 1 of the
    # lower-tag atom: its partner above; slot 2 of the higher: its partner below)
    with open(f"ncf-chains{suffix}-l0.lmp", "w") as f:
        f.write(f"# per-bond reference lengths of data.ncf-chains{suffix} for bond_style ncf/chain "
                "(written by make_scene.py)\n")
        for (t, a, b), l in zip(bonds, l0):
            f.write(f"set atom {a} i2_ncf_dtag[1] {b - a} d2_ncf_l0[1] {l * length!r}\n")
            f.write(f"set atom {b} i2_ncf_dtag[2] {a - b} d2_ncf_l0[2] {l * length!r}\n")


write("", 1.0, 1.0)
write("-micro", 1e6, 1e15)
