#!/usr/bin/env python3
"""Compacted fibrous mat for the pair ncf/contact bench (geometric construction, no simulation).

Layers of straight parallel chains (diameter 69 um, mesh 0.2 mm) with the angles of a quadriaxial
NCF (0, 90, 45, -45 degrees, repeated), in-plane spacing chosen for the requested fibre volume
fraction, layers 0.95 diameters apart (every crossing of two neighbouring layers is a contact with
3.5 um penetration). Periodic in x and y: each line of a layer is periodic, one chain per line,
0.9 of the line's periodic length long, at a random position along it.
Usage: make_mat.py OUT.data [--side 6e-3] [--layers 16] [--vf 0.45] [--seed 1]
"""
import argparse
import math
import random

p = argparse.ArgumentParser()
p.add_argument("out")
p.add_argument("--side", type=float, default=6e-3)
p.add_argument("--layers", type=int, default=16)
p.add_argument("--vf", type=float, default=0.45)
p.add_argument("--mesh", type=float, default=2e-4)
p.add_argument("--diam", type=float, default=69e-6)
p.add_argument("--seed", type=int, default=1)
a = p.parse_args()
random.seed(a.seed)

D, L = a.diam, a.side
dz = 0.95 * D
area = math.pi * D * D / 4
spacing = area / (a.vf * dz)  # in-plane distance of parallel chains for the volume fraction
rho_a = 890.0 * area  # mass per length of a carbon chain (phi = 0.5)

chains = []
for layer in range(a.layers):
    ang = [0, 90, 45, -45][layer % 4]
    z = (layer + 0.5) * dz
    if ang in (0, 90):
        n = max(1, round(L / spacing))
        period = L
        offs = [(k + random.random() * 0.2) * L / n for k in range(n)]
        for o in offs:
            length = 0.9 * period
            s0 = random.random() * L
            if ang == 0:
                p0, d = (s0, o), (1.0, 0.0)
            else:
                p0, d = (o, s0), (0.0, 1.0)
            chains.append((p0, d, length, z))
    else:
        # lines x -+ y = c: periodic with period L*sqrt(2) along the line; normal spacing L/(n sqrt 2)
        n = max(1, round(L / (spacing * math.sqrt(2))))
        period = L * math.sqrt(2)
        sgn = 1.0 if ang == 45 else -1.0
        for k in range(n):
            c = (k + random.random() * 0.2) * L / n
            length = 0.9 * period
            t0 = random.random() * L
            p0 = (t0 + c, sgn * t0) if sgn > 0 else (t0 + c, -t0)
            d = (1 / math.sqrt(2), sgn / math.sqrt(2))
            chains.append((p0, d, length, z))

atoms, bonds = [], []
for ci, (p0, d, length, z) in enumerate(chains):
    nseg = max(1, round(length / a.mesh))
    base = len(atoms)
    for k in range(nseg + 1):
        s = length * k / nseg
        x, y = p0[0] + s * d[0], p0[1] + s * d[1]
        ix, iy = math.floor(x / L), math.floor(y / L)
        atoms.append((ci + 1, x - ix * L, y - iy * L, z, ix, iy))
    for k in range(nseg):
        bonds.append((base + k + 1, base + k + 2))

mass = rho_a * a.mesh
with open(a.out, "w") as f:
    f.write(f"compacted mat, Vf {a.vf}, {len(chains)} chains\n\n")
    f.write(f"{len(atoms)} atoms\n1 atom types\n{len(bonds)} bonds\n1 bond types\n\n")
    # z: the box faces are the compaction plates (fix wall/harmonic, cutoff dz/2 in in.ncf)
    f.write(f"0 {L!r} xlo xhi\n0 {L!r} ylo yhi\n0 {a.layers * dz!r} zlo zhi\n\n")
    f.write(f"Masses\n\n1 {mass!r}\n\nAtoms # bond\n\n")
    for i, (m, x, y, z, ix, iy) in enumerate(atoms):
        f.write(f"{i + 1} {m} 1 {x!r} {y!r} {z!r} {ix} {iy} 0\n")
    f.write("\nBonds\n\n")
    for i, (b0, b1) in enumerate(bonds):
        f.write(f"{i + 1} 1 {b0} {b1}\n")
print(f"{len(atoms)} nodes, {len(chains)} chains, spacing {spacing:.4g} m, Vf {a.vf}")
