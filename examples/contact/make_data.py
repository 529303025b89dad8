#!/usr/bin/env python3
"""Data files of the pair ncf/contact examples (deterministic).

crossed.data: two straight chains (yarns) of 69 um, mesh 0.1 mm, 2 mm long, crossing at 90 deg,
              the upper one 1.1 diameters above the lower one.
mat.data:     a small layered mat: 4 layers (0, 90, 45, -45 deg) of parallel chains, 1.2 mm
              periodic box in x and y, mesh 0.1 mm, layers 1.3 diameters apart (no contact yet).
Node masses: chain of carbon, phi = 0.5 (890 kg/m^3), lumped per mesh length.
"""
import math
import random

D = 69e-6
RHO_A = 890.0 * math.pi * D * D / 4


def write(path, chains, box, mesh, title):
    atoms, bonds = [], []
    for ci, pts in enumerate(chains):
        base = len(atoms)
        for p in pts:
            img = [0, 0, 0]
            q = list(p)
            for d in range(3):
                if box[d][2]:  # periodic: wrap with image flag
                    lo, hi = box[d][0], box[d][1]
                    img[d] = math.floor((p[d] - lo) / (hi - lo))
                    q[d] = p[d] - img[d] * (hi - lo)
            atoms.append((ci + 1, q, img))
        for k in range(len(pts) - 1):
            bonds.append((base + k + 1, base + k + 2))
    with open(path, "w") as f:
        f.write(f"{title}\n\n{len(atoms)} atoms\n1 atom types\n{len(bonds)} bonds\n1 bond types\n\n")
        for d, n in enumerate("xyz"):
            f.write(f"{box[d][0]!r} {box[d][1]!r} {n}lo {n}hi\n")
        f.write(f"\nMasses\n\n1 {RHO_A * mesh!r}\n\nAtoms # bond\n\n")
        for i, (m, q, img) in enumerate(atoms):
            f.write(f"{i + 1} {m} 1 {q[0]!r} {q[1]!r} {q[2]!r} {img[0]} {img[1]} {img[2]}\n")
        f.write("\nBonds\n\n")
        for i, b in enumerate(bonds):
            f.write(f"{i + 1} 1 {b[0]} {b[1]}\n")


def line(p0, p1, n):
    return [tuple(p0[d] + (p1[d] - p0[d]) * k / n for d in range(3)) for k in range(n + 1)]


# two crossed yarns
mesh = 1e-4
crossed = [line((-1e-3, 0, 0), (1e-3, 0, 0), 20), line((0.03e-3, -1e-3, 1.1 * D), (0.03e-3, 1e-3, 1.1 * D), 20)]
write("crossed.data", crossed, [(-1.5e-3, 1.5e-3, False), (-1.5e-3, 1.5e-3, False), (-0.5e-3, 0.5e-3, False)],
      mesh, "two crossed yarns (pair ncf/contact example)")

# small layered mat
random.seed(3)
side, dz, spacing = 1.2e-3, 1.3 * D, 2.0e-4
chains = []
for layer, ang in enumerate([0, 90, 45, -45]):
    z = (layer + 0.5) * dz
    if ang in (0, 90):
        n = round(side / spacing)
        for k in range(n):
            o = (k + 0.5) * side / n
            s0 = random.random() * side
            length = 0.9 * side
            if ang == 0:
                chains.append(line((s0, o, z), (s0 + length, o, z), round(length / mesh)))
            else:
                chains.append(line((o, s0, z), (o, s0 + length, z), round(length / mesh)))
    else:
        n = round(side / (spacing * math.sqrt(2)))
        sgn = 1 if ang == 45 else -1
        for k in range(n):
            c = (k + 0.5) * side / n
            t0 = random.random() * side
            length = 0.9 * side * math.sqrt(2)
            p0 = (t0 + c, sgn * t0, z)
            d = (1 / math.sqrt(2), sgn / math.sqrt(2), 0)
            chains.append(line(p0, tuple(p0[i] + length * d[i] for i in range(3)), round(length / mesh)))
write("mat.data", chains, [(0.0, side, True), (0.0, side, True), (0.0, 4 * dz, False)], mesh,
      "small layered mat (pair ncf/contact example)")
print(f"crossed.data: {sum(len(c) for c in crossed)} nodes; mat.data: {sum(len(c) for c in chains)} nodes, {len(chains)} chains")
