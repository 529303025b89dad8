#!/usr/bin/env python3
"""Writes network.data for the chain-network example: two fibrous layers of straight chains
(0 deg along x, 90 deg along y) and a few stitching-yarn chains along x, every chain a ring closed
across the periodic box, with the NCF_CHAIN_L0 section of bond_style ncf/chain.

Standard library only. Usage: make_data.py OUT.data
"""
import math
import sys

A = 2.0e-4          # element (mesh) length [m]
N = 20              # elements per chain = box length / A
L = N * A           # box length in x and y [m]
LZ = 1.0e-3         # box height [m]
D_F, RHO_F = 69e-6, 905.0     # fibre chain: diameter [m], chain density [kg/m^3] (Table 3, 0/90 NCF)
D_Y, RHO_Y = 88e-6, 1250.0    # stitching yarn chain (Table 3)
N_YARN = 4          # yarn chains along x


def main(path):
    atoms, bonds = [], []   # atoms: (type, x, y, z, mol); bonds: (type, i, j)
    mol = 0

    def ring(atype, btype, start, step):
        nonlocal mol
        mol += 1
        first = len(atoms) + 1
        for k in range(N):
            atoms.append((atype, start[0] + k * step[0], start[1] + k * step[1], start[2], mol))
        for k in range(N):
            bonds.append((btype, first + k, first + (k + 1) % N))

    for j in range(N):                          # 0 deg layer
        ring(1, 1, (0.0, (j + 0.5) * A, 0.30e-3), (A, 0.0))
    for i in range(N):                          # 90 deg layer
        ring(2, 2, ((i + 0.5) * A, 0.0, 0.50e-3), (0.0, A))
    for j in range(N_YARN):                     # stitching yarn
        ring(3, 3, (0.25 * A, (j + 0.5) * L / N_YARN, 0.70e-3), (A, 0.0))

    # lumped masses: every node of a ring carries one element's mass
    m_f = RHO_F * math.pi / 4 * D_F ** 2 * A
    m_y = RHO_Y * math.pi / 4 * D_Y ** 2 * A
    with open(path, "w") as f:
        f.write("USER-NCF chain-network example (make_data.py)\n\n")
        f.write(f"{len(atoms)} atoms\n3 atom types\n{len(bonds)} bonds\n3 bond types\n\n")
        f.write(f"0 {L!r} xlo xhi\n0 {L!r} ylo yhi\n0 {LZ!r} zlo zhi\n\n")
        f.write(f"Masses\n\n1 {m_f!r}\n2 {m_f!r}\n3 {m_y!r}\n\nAtoms # bond\n\n")
        for i, (t, x, y, z, m) in enumerate(atoms, 1):
            f.write(f"{i} {m} {t} {x!r} {y!r} {z!r}\n")
        f.write("\nBonds\n\n")
        for b, (t, i, j) in enumerate(bonds, 1):
            f.write(f"{b} {t} {i} {j}\n")
        # per-bond reference length: on each atom, partner tag minus own tag and L0
        slots = {i: [] for i in range(1, len(atoms) + 1)}
        for t, i, j in bonds:
            slots[i].append((j - i, A))
            slots[j].append((i - j, A))
        f.write("\nNCF_CHAIN_L0\n\n")
        for i in range(1, len(atoms) + 1):
            (d1, l1), (d2, l2) = slots[i]
            f.write(f"{i} {d1} {d2} {l1!r} {l2!r}\n")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "network.data")
