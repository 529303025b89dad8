#!/usr/bin/env python3
"""Data files of the pair ncf/contact examples (deterministic).

crossed.data: two straight chains (yarns) of 69 um, mesh 0.1 mm, 2 mm long, crossing at 90 deg,
              the upper one 1.1 diameters above the lower one.
mat.data:     a small layered mat: 4 layers (0, 90, 45, -45 deg) of parallel chains, 1.2 mm
              periodic box in x and y, mesh 0.1 mm, layers 1.3 diameters apart (no contact yet).
capstan.data: a rope (69 um chain, mesh 0.05 mm, type 1) wrapped by half a turn over a drum (a
              straight chain of 0.5 mm diameter along z, type 2, held fixed by in.capstan), its
              two legs hanging 1 mm down; the rope's segments are tangent to the contact circle.
Node masses: chain of carbon, phi = 0.5 (890 kg/m^3), lumped per mesh length.
"""
import math
import random

D = 69e-6
RHO_A = 890.0 * math.pi * D * D / 4


def write(path, chains, box, mesh, title, types=None, masses=None):
    """chains: node lists; types: atom (and bond) type per chain (default 1); masses: node mass
    per type (default: the 69 um chain's mass per mesh length)"""
    types = types or [1] * len(chains)
    masses = masses or {1: RHO_A * mesh}
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
            atoms.append((ci + 1, types[ci], q, img))
        for k in range(len(pts) - 1):
            bonds.append((types[ci], base + k + 1, base + k + 2))
    nt = len(masses)
    with open(path, "w") as f:
        f.write(f"{title}\n\n{len(atoms)} atoms\n{nt} atom types\n{len(bonds)} bonds\n{nt} bond types\n\n")
        for d, n in enumerate("xyz"):
            f.write(f"{box[d][0]!r} {box[d][1]!r} {n}lo {n}hi\n")
        f.write("\nMasses\n\n" + "".join(f"{t} {m!r}\n" for t, m in sorted(masses.items())))
        f.write("\nAtoms # bond\n\n")
        for i, (m, t, q, img) in enumerate(atoms):
            f.write(f"{i + 1} {m} {t} {q[0]!r} {q[1]!r} {q[2]!r} {img[0]} {img[1]} {img[2]}\n")
        f.write("\nBonds\n\n")
        for i, b in enumerate(bonds):
            f.write(f"{i + 1} {b[0]} {b[1]} {b[2]}\n")


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
# capstan: rope over a drum, wrap angle pi
drum_d, rope_mesh, leg = 0.5e-3, 5e-5, 1e-3
rc = 0.5 * (drum_d + D)                        # contact circle of the rope's axis
narc = math.ceil(math.pi * rc / rope_mesh)     # arc elements
ra = rc / math.cos(0.5 * math.pi / narc)       # arc nodes: the chords touch the circle
nleg = round(leg / rope_mesh)
rope = line((-ra, -leg, 0.0), (-ra, 0.0, 0.0), nleg)[:-1]
rope += [(-ra * math.cos(math.pi * k / narc), ra * math.sin(math.pi * k / narc), 0.0) for k in range(narc)]
rope += line((ra, 0.0, 0.0), (ra, -leg, 0.0), nleg)
drum = line((0.0, 0.0, -0.45e-3), (0.0, 0.0, 0.45e-3), 9)
write("capstan.data", [rope, drum], [(-1.5e-3, 1.5e-3, False), (-1.5e-3, 1.0e-3, False), (-0.5e-3, 0.5e-3, False)],
      rope_mesh, "rope over a drum, half a turn (pair ncf/contact capstan example)", types=[1, 2],
      masses={1: RHO_A * rope_mesh, 2: 890.0 * math.pi * drum_d ** 2 / 4 * 1e-4})
print(f"capstan.data: {len(rope)} rope nodes, {len(drum)} drum nodes")
print(f"crossed.data: {sum(len(c) for c in crossed)} nodes; mat.data: {sum(len(c) for c in chains)} nodes, {len(chains)} chains")
