#!/usr/bin/python3
"""Cost of ncf-perm's solver against the grid size, measured in one run (doc/ncf_perm.md, "Cost").

  /usr/bin/python3 bench/perm_cost.py [--solver build/ncf-perm-solve] [--sizes 32,48,64,96,128]
                                      [--iters 40] [--threads 1]

Each grid is n^3 cells of a fibrous medium (random chain bundles, vf 0..0.5 with directions, and
a few solid cells), solved for one load with a fixed number of iterations (the tolerance out of
reach), so that the time per iteration is measured apart from the convergence. Prints per grid
the time per iteration, the memory the solver reports and the peak resident memory of the run,
and the time per iteration divided by N log2 N relative to the smallest grid (flat if the cost
grows as N log N), and the largest grid that fits 24 GiB at the measured memory per cell.
Timings are for this machine and load; ratios within one run are what to compare.
"""
import argparse
import math
import os
import re
import resource
import subprocess
import sys
import tempfile

import numpy as np


def grid(n, seed=1):
    rng = np.random.default_rng(seed)
    x = np.arange(n) + 0.5
    X, Y, Z = np.meshgrid(x, x, x, indexing="ij")
    vf = np.zeros((n, n, n))
    dr = np.zeros((n, n, n, 3))
    # bundles along x and along y at random positions, radius n/12 (periodic distances)
    for k in range(12):
        along = k % 2
        c = rng.uniform(0, n, 2)
        a, b = (Y, Z) if along == 0 else (X, Z)
        da = (a - c[0] + n / 2) % n - n / 2
        db = (b - c[1] + n / 2) % n - n / 2
        inside = da * da + db * db < (n / 12) ** 2
        vf[inside] = 0.5
        dr[inside] = [1, 0, 0] if along == 0 else [0, 1, 0]
    vf[: max(1, n // 16), : max(1, n // 16), : max(1, n // 16)] = 1.0
    # VTK order: x fastest -> array index [z, y, x]
    return np.ascontiguousarray(vf.transpose(2, 1, 0)), np.ascontiguousarray(dr.transpose(2, 1, 0, 3))


def main():
    p = argparse.ArgumentParser()
    here = os.path.dirname(os.path.abspath(__file__))
    p.add_argument("--solver", default=os.path.join(here, "..", "build", "ncf-perm-solve"))
    p.add_argument("--sizes", default="32,48,64,96,128")
    p.add_argument("--iters", type=int, default=40)
    p.add_argument("--threads", type=int, default=1)
    a = p.parse_args()
    sizes = [int(s) for s in a.sizes.split(",")]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in sorted(sizes):
            vf, dr = grid(n)
            raw = os.path.join(tmp, "g.raw")
            h = 1e-5
            with open(raw, "wb") as f:
                f.write(("NCFPERM 1 %d %d %d %r %r %r 3\n" % (n, n, n, h, h, h)).encode())
                f.write(vf.astype("<f8").tobytes())
                f.write(dr.astype("<f8").tobytes())
            del vf, dr
            out = subprocess.run([a.solver, raw, "--fibre-radius", "3.5e-6", "--loads", "x",
                                  "--max-iter", str(a.iters), "--tol", "1e-15", "--threads",
                                  str(a.threads), "--quiet"], capture_output=True, text=True)
            if out.returncode not in (0, 2):
                sys.exit("perm_cost: the solver failed on %d^3: %s" % (n, out.stderr))
            m = re.search(r"iterations (\d+) in all, (\S+) s per iteration \((\d+)% in the transforms\), "
                          r"memory (\S+) MiB \((\d+) bytes per cell\)", out.stdout)
            rss = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024.0    # monotonic: sizes grow
            N = n ** 3
            rows.append((n, N, float(m.group(2)), int(m.group(3)), float(m.group(5)), rss / N))
    print("| grid | cells N | s / iteration | in FFTs | solver bytes / cell | peak RSS bytes / cell "
          "| (s / it) / (N log2 N), relative |")
    print("|---|---|---|---|---|---|---|")
    n0, N0, t0 = rows[0][0], rows[0][1], rows[0][2]
    for n, N, t, fft, b, r in rows:
        rel = (t / (N * math.log2(N))) / (t0 / (N0 * math.log2(N0)))
        print("| %d^3 | %d | %.4g | %d %% | %.0f | %.0f | %.2f |" % (n, N, t, fft, b, r, rel))
    big = rows[-1]
    per_cell = max(big[4], big[5])
    cells = 24 * 1024 ** 3 / per_cell
    print("\nlargest grid in 24 GiB at %.0f bytes per cell (the larger of solver and peak RSS of the "
          "largest grid): %.3g cells, a cube of %d^3" % (per_cell, cells, int(cells ** (1 / 3))))


if __name__ == "__main__":
    main()
