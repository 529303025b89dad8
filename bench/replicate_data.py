#!/usr/bin/env python3
"""R x R in-plane copies of a manufacturing stage's data file (PREFIX.STAGE.data of
examples/manufacturing, written by stage_end.lmp), for the timing of larger RVEs in
bench/scaling.sh (LAMMPS's replicate refuses the per-atom fixes NCF_NODE and NCF_CHAIN_L0).

Every copy is the elementary state shifted by whole box lengths; a bond that crosses a periodic
face joins the neighbouring copy (nearest image; image flags are set to 0); the chain ends at the inner seams
stay free (their end flag in NCF_NODE is cleared: fix ncf/pbc ties the outer faces only). The
Pair/Bond Coeffs sections are left out (the stage settings give them). Needle positions
(PREFIX.needles) are copied the same way with --needles.
Usage: replicate_data.py IN.data OUT.data R [--needles IN OUT]
"""
import argparse
import math
import sys

p = argparse.ArgumentParser()
p.add_argument("src")
p.add_argument("out")
p.add_argument("r", type=int)
p.add_argument("--needles", nargs=2)
a = p.parse_args()
R = a.r

lines = open(a.src).read().split("\n")
header, sections, cur = [], {}, None
names = ("Masses", "Bond Coeffs", "Pair Coeffs", "PairIJ Coeffs", "Atoms", "Velocities", "Bonds",
         "NCF_NODE", "NCF_CHAIN_L0")
for ln in lines:
    key = next((n for n in names if ln.startswith(n)), None)
    if key:
        cur = key
        sections[cur] = [ln, []]
        continue
    if cur is None:
        header.append(ln)
    elif ln.strip():
        sections[cur][1].append(ln)

# the angles of a 'bending bundle' state are not replicated (their section would be read as part
# of the one before it): refuse rather than write a wrong file
for ln in header + [ln for ln in lines if ln.startswith("Angles")]:
    w = ln.split()
    if (len(w) == 2 and w[1] == "angles" and int(w[0]) > 0) or (w and w[0] == "Angles"):
        sys.exit(f"replicate_data.py: {a.src} has angles (ncf-gen 'bending bundle'); only states "
                 "without angles can be replicated")

box = {}
for ln in header:
    w = ln.split()
    if len(w) == 4 and w[2].endswith("lo"):
        box[w[2][0]] = (float(w[0]), float(w[1]))
(xlo, xhi), (ylo, yhi) = box["x"], box["y"]
lx, ly = xhi - xlo, yhi - ylo
atoms = [ln.split() for ln in sections["Atoms"][1]]
natoms = len(atoms)
maxid = max(int(w[0]) for w in atoms)
maxmol = max(int(w[1]) for w in atoms)
nbonds = len(sections["Bonds"][1])
pos = {}
out = []
for ln in header:
    w = ln.split()
    if len(w) == 2 and w[1] == "atoms":
        ln = f"{natoms * R * R} atoms"
    elif len(w) == 2 and w[1] == "bonds":
        ln = f"{nbonds * R * R} bonds"
    elif len(w) == 4 and w[2] == "xlo":
        ln = f"{xlo!r} {xlo + R * lx!r} xlo xhi"
    elif len(w) == 4 and w[2] == "ylo":
        ln = f"{ylo!r} {ylo + R * ly!r} ylo yhi"
    out.append(ln)
while out and not out[-1].strip():
    out.pop()
out.append("")


def copies():
    for i in range(R):
        for j in range(R):
            yield i, j, (i * R + j)


def section(name, rows):
    out.extend([sections[name][0], ""] + rows + [""])


section("Masses", sections["Masses"][1])
# positions in the box (image flags not used: they need not be consistent across a bond); a
# bond a-b of copy (i, j) joins b of the copy where b is a's nearest image
xy = {int(w[0]): (float(w[3]), float(w[4])) for w in atoms}


def kof(i, j):
    return (i % R) * R + (j % R)


def partner(a, b, i, j):
    """copy index of b bonded to a of copy (i, j)"""
    dx, dy = xy[b][0] - xy[a][0], xy[b][1] - xy[a][1]
    return kof(i - round(dx / lx), j - round(dy / ly))


rows = []
for i, j, k in copies():
    for w in atoms:
        x2, y2 = float(w[3]) + i * lx, float(w[4]) + j * ly
        tag = int(w[0]) + k * maxid
        pos[tag] = (x2, y2)
        rows.append(f"{tag} {int(w[1]) + k * maxmol} {w[2]} {x2!r} {y2!r} {w[5]} 0 0 {w[8]}")
section("Atoms", rows)
if "Velocities" in sections:
    section("Velocities", [f"{int(w.split()[0]) + k * maxid} " + " ".join(w.split()[1:])
                           for _, _, k in copies() for w in sections["Velocities"][1]])
rows = []
for i, j, k in copies():
    for w in sections["Bonds"][1]:
        b = w.split()
        a1, a2 = int(b[2]), int(b[3])
        rows.append(f"{int(b[0]) + k * nbonds} {b[1]} {a1 + k * maxid} {a2 + partner(a1, a2, i, j) * maxid}")
section("Bonds", rows)
# end flags 1, 2: x faces; 3, 4: y faces; cleared away from the outer faces
band_x, band_y = 0.1 * lx, 0.1 * ly
rows = []
for _, _, k in copies():
    for w in sections["NCF_NODE"][1]:
        v = w.split()
        tag = int(v[0]) + k * maxid
        end = int(v[2])
        x, y = pos[tag]
        if end in (1, 2) and xlo + band_x < x < xlo + R * lx - band_x:
            end = 0
        if end in (3, 4) and ylo + band_y < y < ylo + R * ly - band_y:
            end = 0
        rows.append(f"{tag} {v[1]} {end}")
section("NCF_NODE", rows)
# NCF_CHAIN_L0 holds the tag differences to the bond partners (0: none): shifted by the copy
rows = []
for i, j, k in copies():
    for w in sections["NCF_CHAIN_L0"][1]:
        v = w.split()
        a0 = int(v[0])
        d = []
        for dt in (int(v[1]), int(v[2])):
            if dt != 0 and (a0 + dt) in xy:
                dt += (partner(a0, a0 + dt, i, j) - k) * maxid
            d.append(str(dt))
        rows.append(f"{a0 + k * maxid} {d[0]} {d[1]} {v[3]} {v[4]}")
section("NCF_CHAIN_L0", rows)
open(a.out, "w").write("\n".join(out) + "\n")

if a.needles:
    with open(a.needles[1], "w") as f:
        for ln in open(a.needles[0]):
            w = ln.split("#")[0].split()
            if len(w) >= 2:
                for i in range(R):
                    for j in range(R):
                        f.write(f"{float(w[0]) + i * lx!r} {float(w[1]) + j * ly!r}\n")
