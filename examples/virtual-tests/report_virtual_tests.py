#!/usr/bin/env python3
"""Report of the virtual tests of as-manufactured fabrics (doc/howto_virtual_tests.md).

Reads what examples/virtual-tests/in.compaction and in.shear wrote (PREFIX.compaction.dat,
PREFIX.shear-pos.dat, PREFIX.shear-neg.dat, PREFIX.settings.lmp) and writes a Markdown report
with PNG plots: the compaction curve (pressure against V_f and thickness, loading and
unloading), the thickness at 1 bar, the fit of the loading branch to Toll's law
P = k E_f (V_f^n - V_0^n), the hysteresis, and for the shear test the work per unit area w, the
shear force per unit length F_s = dw/dtheta (picture-frame normalised, energy-equivalent), the
yarn tension, the thickness and the out-of-plane displacement against the shear angle, in both
senses, and their asymmetry.

Usage: report_virtual_tests.py PREFIX [PREFIX ...] --dir DIR [--dir DIR ...] --out REPORT.md
With several --dir (e.g. one per seed) every PREFIX is read from each: the tables give the mean
and the sample SD, the plots the mean and the band of the seeds.
"""
import argparse
import math
import os
import re
import sys

import numpy as np

BAR = 1e5


def fail(msg):
    sys.exit(f"report_virtual_tests.py: {msg}")


def settings(path):
    """The numeric variables of an ncf-gen settings file."""
    out = {}
    try:
        with open(path) as f:
            for line in f:
                m = re.match(r"variable\s+(\w+)\s+(?:equal|index)\s+([-+0-9.eE]+)", line)
                if m:
                    out[m.group(1)] = float(m.group(2))
    except OSError as e:
        fail(f"cannot read {path}: {e.strerror}")
    for key in ("ncf_Lx", "ncf_Ly", "ncf_d_fibre", "ncf_thickness"):
        if key not in out:
            fail(f"{path} has no variable {key}: not the settings of an ncf-gen fabric")
    return out


def table(path, ncol):
    """The numeric rows of a record written by fix print (comment lines skipped)."""
    if not os.path.isfile(path):
        return None
    rows = []
    with open(path) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            v = line.split()
            if len(v) != ncol:
                fail(f"{path}: a line with {len(v)} columns, expected {ncol}: {line.strip()[:80]}")
            rows.append([float(x) for x in v])
    if not rows:
        fail(f"{path}: no records")
    a = np.array(rows)
    # a resumed test appends: keep the last record of each step
    _, last = np.unique(a[::-1, 0], return_index=True)
    return a[::-1][np.sort(last)] if len(last) < len(a) else a


# ------------------------------------------------------------------ compaction

def toll_fit(vf, p):
    """Least-squares fit of Toll's law P = A (V^n - V0^n) to the loading branch; A [Pa], n, V0,
    their standard errors, and the RMS residual [Pa]. Fitted as P = P1 ((V/V1)^n - (V0/V1)^n)
    with V1 the largest V_f (well scaled: A = P1 / V1^n, its error from the covariance)."""
    from scipy.optimize import curve_fit

    v1 = float(vf.max())

    def law(v, p1, n, v0):
        return p1 * (np.power(v / v1, n) - np.power(v0 / v1, n))

    guess = (float(p.max()), 5.0, 0.99 * float(vf.min()))
    try:
        par, cov = curve_fit(law, vf, p, p0=guess, maxfev=20000,
                             bounds=((0.0, 0.5, 0.0), (np.inf, 200.0, float(vf.min()))))
    except (RuntimeError, ValueError):
        return None
    p1, n, v0 = par
    a = p1 / v1 ** n
    # A = p1 v1^-n: dA/dp1 = A/p1, dA/dn = -A ln v1
    jac = np.array([a / p1, -a * math.log(v1), 0.0])
    sa = float(math.sqrt(max(jac @ cov @ jac, 0.0)))
    err = (sa, float(math.sqrt(cov[1, 1])), float(math.sqrt(cov[2, 2])))
    rms = float(np.sqrt(np.mean((law(vf, *par) - p) ** 2)))
    return (a, n, v0), err, rms


def compaction(d, prefix, s):
    a = table(os.path.join(d, f"{prefix}.compaction.dat"), 12)
    if a is None:
        return None
    branch, gap, vf, pu, pl, yarn, thick, ke = a[:, 1], a[:, 2], a[:, 3], a[:, 4], a[:, 5], \
        a[:, 6], a[:, 7], a[:, 8]
    area = s["ncf_Lx"] * s["ncf_Ly"]
    # branch c > 0: loading in cycle c, -c: unloading; the curve's figures from the first cycle
    load = branch == 1
    unload = branch == -1
    r = {"gap": gap, "vf": vf, "p": pu, "pl": pl, "yarn": yarn, "load": load, "unload": unload}
    pmax = pu[load].max()
    r["pmax"] = pmax
    # the thickness and V_f at 1 bar on the loading branch (the first crossing)
    gl, pl_, vl = gap[load], pu[load], vf[load]
    k = np.nonzero(pl_ >= BAR)[0]
    if len(k) and k[0] > 0:
        i = k[0]
        t = (BAR - pl_[i - 1]) / (pl_[i] - pl_[i - 1])
        r["h1bar"] = gl[i - 1] + t * (gl[i] - gl[i - 1])
        r["vf1bar"] = vl[i - 1] + t * (vl[i] - vl[i - 1])
    # works per unit area in each cycle: done on the fabric while loading, given back while
    # unloading, and the hysteresis (their difference over the loading work)
    r["cycles"] = []
    for c in range(1, int(branch.max()) + 1):
        lc, uc = branch == c, branch == -c
        wl = float(-np.trapz(pu[lc], gap[lc]))
        wu = float(np.trapz(pu[uc], gap[uc])) if uc.any() else float("nan")
        r["cycles"].append((wl, wu, (wl - wu) / wl if wl > 0 else float("nan")))
    r["w_load"], r["w_unload"], r["hysteresis"] = r["cycles"][0]
    # the kinetic energy while the plate presses (the fabric's own residual motion before the
    # first contact is not the test's)
    pressing = pu > 0
    r["ke_over_work"] = float(ke[pressing].max() / (r["w_load"] * area)) \
        if r["w_load"] > 0 and pressing.any() else float("nan")
    # Toll's law on the loading branch above 2 % of pmax (the first contacts are the plate
    # finding the fabric, not the fabric's law)
    fit_on = load & (pu > 0.02 * pmax)
    r["fit"] = toll_fit(vf[fit_on], pu[fit_on]) if fit_on.sum() >= 6 else None
    r["yarn_turn"] = float(yarn[load][np.argmax(pu[load])])
    r["yarn_start"] = float(yarn[0])
    return r


# ------------------------------------------------------------------ shear

def shear_angle(frame, lx, ly, xy, lx0, ly0):
    if frame == "bias":
        return math.pi / 2 - 2 * np.arctan((ly / ly0) / (lx / lx0))
    return np.arctan2(xy, ly)


def shear(d, prefix, sense, s):
    a = table(os.path.join(d, f"{prefix}.shear-{sense}.dat"), 17)
    if a is None:
        return None
    lx, ly, xy = a[:, 1], a[:, 2], a[:, 3]
    W = a[:, 4:10]    # xx yy zz xy xz yz, the virial P V [N m]
    lx0, ly0 = s["ncf_Lx"], s["ncf_Ly"]
    frame = "square" if np.any(np.abs(xy) > 1e-12 * ly0) else "bias"
    th = shear_angle(frame, lx, ly, xy, lx0, ly0)
    # the work of the box on the fabric, -sum W_ab L_ab dt (trapezoid between records), from the
    # undeformed box (the first record is a few steps in: the segment from the start is added
    # with the first record's stress)
    lxs = np.concatenate(([lx0], lx))
    lys = np.concatenate(([ly0], ly))
    xys = np.concatenate(([0.0], xy))
    Ws = np.vstack((W[:1], W))
    dlx, dly, dxy = np.diff(lxs), np.diff(lys), np.diff(xys)
    mlx, mly, mxy = 0.5 * (lxs[1:] + lxs[:-1]), 0.5 * (lys[1:] + lys[:-1]), 0.5 * (xys[1:] + xys[:-1])
    mW = 0.5 * (Ws[1:] + Ws[:-1])
    dwork = -(mW[:, 0] * dlx / mlx + mW[:, 1] * dly / mly + mW[:, 3] * (dxy / mly - dlx * mxy / (mlx * mly)))
    work = np.cumsum(dwork)
    A0 = lx0 * ly0
    w = work / A0
    ths = np.abs(th)
    # F_s = dw/dtheta over windows of about 1 degree
    deg = np.degrees(ths)
    grid = np.arange(1.0, math.floor(deg.max()) + 1e-9, 1.0)
    wg = np.interp(grid, deg, w)
    fs = np.gradient(wg, np.radians(grid))
    pe = a[:, 10]
    return {"theta": th, "deg": deg, "w": w, "grid": grid, "fs": fs, "yarn": a[:, 12],
            "thick": a[:, 13], "wrinkle": a[:, 14], "pbc": a[:, 16], "frame": frame,
            "dpe": (pe - pe[0]) / A0, "ke": a[:, 11]}


# ------------------------------------------------------------------ report

def stats(values):
    v = np.array([x for x in values if x is not None and np.isfinite(x)])
    if len(v) == 0:
        return "–"
    if len(v) == 1:
        return f"{v[0]:.4g}"
    return f"{v.mean():.4g} ± {v.std(ddof=1):.2g}"


def band(ax, curves, label, color, style="-"):
    """Mean of the curves (x, y) on a common x and the band of min..max."""
    xs = [c[0] for c in curves if c is not None]
    if not xs:
        return
    lo = max(x.min() for x in xs)
    hi = min(x.max() for x in xs)
    if hi <= lo:
        return
    grid = np.linspace(lo, hi, 200)
    ys = np.array([np.interp(grid, *c) for c in curves if c is not None])
    ax.plot(grid, ys.mean(axis=0), style, color=color, label=label)
    if len(ys) > 1:
        ax.fill_between(grid, ys.min(axis=0), ys.max(axis=0), color=color, alpha=0.25, lw=0)


def save(plt, fig, title, path):
    """Writes a figure as PNG; the Markdown line that shows it (beside the report)."""
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return f"![{title}]({os.path.basename(path)})"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("prefixes", nargs="+")
    ap.add_argument("--dir", action="append", required=True)
    ap.add_argument("--out", required=True)
    args = ap.parse_args()
    for d in args.dir:
        if not os.path.isdir(d):
            fail(f"--dir {d}: no such folder")
    outdir = os.path.dirname(os.path.abspath(args.out))
    if not os.path.isdir(outdir):
        fail(f"--out {args.out}: the folder {outdir} does not exist")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    lines = ["# Virtual tests of the as-manufactured fabric", "",
             f"Seeds/folders: {len(args.dir)} ({', '.join(args.dir)}). Values: mean ± sample SD over "
             "the folders where there are several. Method: doc/howto_virtual_tests.md.", ""]
    for p in args.prefixes:
        sets = [settings(os.path.join(d, f"{p}.settings.lmp")) for d in args.dir]
        s0 = sets[0]
        comp = [compaction(d, p, s) for d, s in zip(args.dir, sets)]
        sh = {sense: [shear(d, p, sense, s) for d, s in zip(args.dir, sets)] for sense in ("pos", "neg")}
        lines += [f"## {p}", ""]
        if any(c is not None for c in comp):
            cs = [c for c in comp if c is not None]
            lines += ["### Compaction", "",
                      "| quantity | value |", "|---|---|",
                      f"| largest pressure | {stats([c['pmax'] / BAR for c in cs])} bar |",
                      f"| thickness at 1 bar | {stats([c.get('h1bar', float('nan')) * 1e3 for c in cs])} mm "
                      f"(sum of t_L {s0['ncf_thickness'] * 1e3:.4g} mm) |",
                      f"| V_f at 1 bar | {stats([c.get('vf1bar', float('nan')) for c in cs])} |",
                      f"| work of loading per area | {stats([c['w_load'] for c in cs])} J/m² |",
                      f"| hysteresis (loading − unloading work) / loading work | {stats([c['hysteresis'] for c in cs])} |",
                      *[f"| hysteresis of cycle {k + 1} | {stats([c['cycles'][k][2] for c in cs if len(c['cycles']) > k])} |"
                        for k in range(1, max(len(c["cycles"]) for c in cs))],
                      f"| largest kinetic energy / loading work | {stats([c['ke_over_work'] for c in cs])} |",
                      f"| yarn tension at the start, at the largest pressure | {stats([c['yarn_start'] for c in cs])} N, "
                      f"{stats([c['yarn_turn'] for c in cs])} N |"]
            fits = [c["fit"] for c in cs if c["fit"] is not None]
            ef = s0.get("ncf_E_fibre")
            if fits:
                k = [f[0][0] / ef for f in fits] if ef else [float("nan")]
                lines += [f"| Toll P = k E_f (V_f^n − V_0^n): k | {stats(k)} (E_f {ef:.4g} Pa; fit SE "
                          f"{fits[0][1][0] / ef:.2g} for the first) |" if ef else "| Toll: E_f unknown |",
                          f"| n | {stats([f[0][1] for f in fits])} (fit SE {fits[0][1][1]:.2g}) |",
                          f"| V_0 | {stats([f[0][2] for f in fits])} (fit SE {fits[0][1][2]:.2g}) |",
                          f"| fit RMS residual | {stats([f[2] / BAR for f in fits])} bar |"]
            else:
                lines += ["| Toll fit | did not converge |"]
            lines.append("")
            fig, ax = plt.subplots(1, 2, figsize=(10, 4))
            band(ax[0], [(c["vf"][c["load"]], c["p"][c["load"]] / BAR) for c in cs], "loading", "C0")
            band(ax[0], [(c["vf"][c["unload"]][::-1], c["p"][c["unload"]][::-1] / BAR) for c in cs
                         if c["unload"].any()], "unloading", "C1")
            if fits:
                v = np.linspace(fits[0][0][2], cs[0]["vf"][cs[0]["load"]].max(), 100)
                a_, n_, v0_ = fits[0][0]
                ax[0].plot(v, a_ * (v ** n_ - v0_ ** n_) / BAR, "k--", lw=0.8, label="Toll fit")
            ax[0].axhline(1.0, color="grey", lw=0.5)
            ax[0].set_xlabel("fibre volume fraction V_f")
            ax[0].set_ylabel("pressure [bar]")
            ax[0].legend()
            band(ax[1], [(c["gap"][c["load"]][::-1] * 1e3, c["p"][c["load"]][::-1] / BAR) for c in cs], "loading", "C0")
            band(ax[1], [(c["gap"][c["unload"]] * 1e3, c["p"][c["unload"]] / BAR) for c in cs
                         if c["unload"].any()], "unloading", "C1")
            ax[1].set_xlabel("thickness (plate gap) [mm]")
            ax[1].set_ylabel("pressure [bar]")
            lines += [save(plt, fig, f"{p}: compaction", os.path.join(outdir, f"{p}.compaction_curve.png")), ""]
        if any(x is not None for x in sh["pos"] + sh["neg"]):
            lines += ["### In-plane shear (picture-frame kinematics, both senses)", "",
                      "| quantity | + sense | − sense | ratio +/− |", "|---|---|---|---|"]
            def at(r, key, deg):
                return None if r is None or r["deg"].max() < deg - 0.5 else float(np.interp(deg, r["deg"], r[key]))
            def fs_at(r, deg):
                return None if r is None or r["grid"].max() < deg else float(np.interp(deg, r["grid"], r["fs"]))
            reach = min((r["grid"].max() for r in sh["pos"] + sh["neg"] if r is not None and len(r["grid"])),
                        default=0)
            for deg in [d for d in (2, 5, 10, 20, 30, 40) if d <= reach]:
                fp = [fs_at(r, deg) for r in sh["pos"]]
                fn = [fs_at(r, deg) for r in sh["neg"]]
                ratio = [a / b for a, b in zip(fp, fn) if a is not None and b is not None and b != 0]
                lines.append(f"| F_s at {deg}° [N/m] | {stats(fp)} | {stats(fn)} | {stats(ratio)} |")
            wmax = max((r["deg"].max() for r in sh["pos"] + sh["neg"] if r is not None), default=0)
            for key, name, scale, unit in (("w", "work per area w", 1, "J/m²"),
                                            ("yarn", "yarn tension", 1, "N"),
                                            ("thick", "thickness", 1e3, "mm"),
                                            ("wrinkle", "RMS out-of-plane displacement", 1e6, "µm")):
                vp = [at(r, key, wmax) for r in sh["pos"]]
                vn = [at(r, key, wmax) for r in sh["neg"]]
                vp = [None if v is None else v * scale for v in vp]
                vn = [None if v is None else v * scale for v in vn]
                ratio = [a / b for a, b in zip(vp, vn) if a is not None and b is not None and b != 0]
                lines.append(f"| {name} at {wmax:.0f}° [{unit}] | {stats(vp)} | {stats(vn)} | {stats(ratio)} |")
            onset = {}
            for sense in ("pos", "neg"):
                vals = []
                for r in sh[sense]:
                    if r is None:
                        continue
                    k = np.nonzero(r["wrinkle"] > 0.5 * s0["ncf_d_fibre"])[0]
                    vals.append(float(r["deg"][k[0]]) if len(k) else None)
                onset[sense] = vals
            lines.append(f"| out-of-plane displacement above d_c/2 from [°] | "
                         f"{stats(onset['pos']) if any(v is not None for v in onset['pos']) else 'not reached'} | "
                         f"{stats(onset['neg']) if any(v is not None for v in onset['neg']) else 'not reached'} | |")
            pbc = max(float(np.max(r["pbc"])) for r in sh["pos"] + sh["neg"] if r is not None)
            lines += ["", f"Largest averaged-PBC violation during the shear: {pbc:.2g} m.",
                      "The + sense stretches the box along x (bias frame: the machine and stitch direction; "
                      "square frame: the y family turns towards +x).", ""]
            fig, ax = plt.subplots(2, 2, figsize=(10, 7))
            for sense, color, label in (("pos", "C3", "+ sense"), ("neg", "C0", "− sense")):
                rs = sh[sense]
                band(ax[0, 0], [(r["grid"], r["fs"]) for r in rs if r is not None], label, color)
                band(ax[0, 1], [(r["deg"], r["w"]) for r in rs if r is not None], label, color)
                band(ax[1, 0], [(r["deg"], r["yarn"]) for r in rs if r is not None], label, color)
                band(ax[1, 1], [(r["deg"], r["thick"] * 1e3) for r in rs if r is not None], label + " thickness", color)
                band(ax[1, 1], [(r["deg"], r["wrinkle"] * 1e3) for r in rs if r is not None], label + " out-of-plane RMS", color, "--")
            ax[0, 0].set_ylabel("shear force F_s = dw/dθ [N/m]")
            ax[0, 1].set_ylabel("work per area w [J/m²]")
            ax[1, 0].set_ylabel("mean yarn tension [N]")
            ax[1, 1].set_ylabel("[mm]")
            for a_ in ax.flat:
                a_.set_xlabel("shear angle |θ| [deg]")
                a_.legend(fontsize=7)
            lines += [save(plt, fig, f"{p}: in-plane shear", os.path.join(outdir, f"{p}.shear_curve.png")), ""]
    with open(args.out, "w") as f:
        f.write("\n".join(x for x in lines if x is not None) + "\n")
    print(f"report: {args.out}")


if __name__ == "__main__":
    main()
