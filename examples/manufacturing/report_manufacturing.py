#!/usr/bin/env python3
"""Report and checks of the manufacturing stages (examples/manufacturing, stages 1-5).

Usage: report_manufacturing.py PREFIX [PREFIX ...] [--dir DIR] [--out FILE]

For each fabric PREFIX it reads, in DIR (default .), what the stages wrote: the logs
PREFIX.STAGE.log (thermo, the stage's summary line, wall time), the data files PREFIX.STAGE.data
and dumps PREFIX.STAGE.dump, the generator's PREFIX.summary and PREFIX.needles, and checks:
  - no pass-through at any stage: the largest chain-chain penetration (whole stage) below half a
    fibre chain diameter, the largest needle penetration too;
  - stage 2: no fibre node and no fibre segment inside a needle at the end of the stroke;
  - stage 3: the yarn overlaps nothing where it is inserted (zero contact force on it);
  - quasi-static: kinetic energy small against the work done / the energy stored;
  - stage 4: the yarn tension against the rod model EA (s - contraction);
  - stage 5: thickness, fibre volume fraction, out-of-balance force, averaged PBC violation.
And, as physics (a verdict, not a check of the code: it does not change the exit status), after
stages 4 and 5: does the stitch hold? The yarn's mean tension against EA s (a stitch holds when
it carries at least HOLD_TENSION and has contracted less than its shrink), and the pressure its
legs put on the fabric beside the plates' at the end of stage 4 and the thickness the fabric
swells to when only the yarn holds it.
Writes a Markdown report (stdout, or --out) and the curve of the plate pressure through the stages
(PREFIX.pressure.png). Exit status 1 if a check fails.
"""
import argparse
import math
import os
import re
import sys

from report_compaction import thermo_blocks    # noqa: E402  (same folder)

STAGES = ["compact", "pierce", "stitch", "pretension", "release"]
# a stitch holds when its yarn carries at least this mean tension [N] (a real NCF's stitching yarn
# is pretensioned to a clear share of EA s, order 0.05-0.5 N for the paper's 5-8 tex PES yarns)
HOLD_TENSION = 0.05
TITLES = {"compact": "1 compaction", "pierce": "2 piercing", "stitch": "3 stitching",
          "pretension": "4 pretension", "release": "5 release"}


class ReportError(Exception):
    pass


def printed(path, tag):
    """key value pairs of the last line starting with tag (the stages' summary lines)."""
    found = None
    for line in open(path):
        if line.startswith(tag + " "):
            w = line.split()[1:]
            found = {}
            for i in range(0, len(w) - 1, 2):
                try:
                    found[w[i]] = float(w[i + 1])
                except ValueError:
                    found[w[i]] = w[i + 1]
    return found


def loop_time(path):
    t, steps = 0.0, 0
    for line in open(path):
        m = re.match(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps", line)
        if m:
            t += float(m.group(1))
            steps += int(m.group(3))
    return t, steps


def read_data(path):
    """Atoms (id -> mol, type, x, y, z), bonds (type, a, b), box, bond coeffs, L0 per bond."""
    box, atoms, bonds, l0, coeffs = {}, {}, [], {}, {}
    section = None
    with open(path) as f:
        for raw in f:
            line = raw.split("#")[0].strip()
            if not line:
                continue
            w = line.split()
            if len(w) >= 4 and w[2] in ("xlo", "ylo", "zlo") and w[3] in ("xhi", "yhi", "zhi"):
                box[w[2][0]] = (float(w[0]), float(w[1]))
                continue
            if w[0][0].isalpha():
                section = w[0] if len(w) == 1 or w[1] != "Coeffs" else w[0] + "Coeffs"
                continue
            if section == "Atoms":
                img = (int(w[6]), int(w[7])) if len(w) >= 9 else (0, 0)
                atoms[int(w[0])] = (int(w[1]), int(w[2]), float(w[3]), float(w[4]), float(w[5]),
                                    img[0], img[1])
            elif section == "Bonds":
                bonds.append((int(w[1]), int(w[2]), int(w[3])))
            elif section == "NCF_CHAIN_L0":
                i = int(w[0])
                for k in (1, 2):
                    d = int(w[k])
                    if d:
                        l0[(min(i, i + d), max(i, i + d))] = float(w[k + 2])
            elif section == "BondCoeffs":
                c = {w[k]: float(w[k + 1]) for k in range(1, len(w) - 1, 2)}
                coeffs[int(w[0])] = c
    if not atoms or not bonds:
        raise ReportError(f"{path}: no Atoms or no Bonds section")
    return box, atoms, bonds, l0, coeffs


def read_dump(path):
    """The one frame of a stage dump: id -> dict of the columns."""
    rows, cols = {}, None
    with open(path) as f:
        for line in f:
            if line.startswith("ITEM: ATOMS"):
                cols = line.split()[2:]
                continue
            if cols and not line.startswith("ITEM"):
                w = line.split()
                if len(w) == len(cols):
                    r = dict(zip(cols, (float(x) for x in w)))
                    rows[int(r["id"])] = r
    if not rows:
        raise ReportError(f"{path}: no atoms")
    return rows


def read_needles(path):
    pts = []
    for line in open(path):
        line = line.split("#")[0].split()
        if len(line) >= 2:
            pts.append((float(line[0]), float(line[1])))
    if not pts:
        raise ReportError(f"{path}: no needle positions")
    return pts


def unwrapped_positions(path):
    """id -> node position with the periodic images undone (x, y), from a data file; and the
    longest box side"""
    box, atoms, _, _, _ = read_data(path)
    lx, ly = box["x"][1] - box["x"][0], box["y"][1] - box["y"][0]
    pos = {i: (a[2] + a[5] * lx, a[3] + a[6] * ly, a[4]) for i, a in atoms.items()}
    return pos, max(lx, ly, box["z"][1] - box["z"][0])


def fibre_diameter(settings):
    """the fibre chain diameter of a generator's settings file (ncf_d_fibre)"""
    for line in open(settings):
        if line.startswith("variable ncf_d_fibre equal"):
            return float(line.split()[3])
    raise ReportError(f"{settings}: no ncf_d_fibre")


def summary_value(path, key):
    for line in open(path):
        if line.strip().startswith(key):
            return line.strip()[len(key):].split()
    raise ReportError(f"{path}: no line '{key}'")


def periodic(d, L):
    return d - L * round(d / L)


def needle_clearance(dump, needles, lx, ly, radius):
    """Smallest horizontal distance of a fibre node and of a fibre segment (bond) to a needle
    axis, over every needle and its periodic images."""
    node_min = math.inf
    for r in dump.values():
        if int(r["i_ncf_layer"]) <= 0:
            continue
        for (nx, ny) in needles:
            node_min = min(node_min, math.hypot(periodic(r["x"] - nx, lx), periodic(r["y"] - ny, ly)))
    return node_min


def segment_needle_clearance(atoms, bonds, needles, lx, ly, layer_types):
    """Closest horizontal approach of any fibre bond to a needle axis (2D point-segment)."""
    best = math.inf
    for (t, a, b) in bonds:
        if t not in layer_types:
            continue
        xa, ya = atoms[a][2], atoms[a][3]
        dx, dy = periodic(atoms[b][2] - xa, lx), periodic(atoms[b][3] - ya, ly)
        l2 = dx * dx + dy * dy
        for (nx, ny) in needles:
            px, py = periodic(nx - xa, lx), periodic(ny - ya, ly)
            u = 0.0 if l2 == 0 else max(0.0, min(1.0, (px * dx + py * dy) / l2))
            best = min(best, math.hypot(px - u * dx, py - u * dy))
    return best


def yarn_tension(data, yarn_type, shrink):
    """Per yarn bond: tension N = EA (r - L0 (1 - s)) / L0 from the data file alone; the yarn's
    contraction 1 - sum r / sum L0; the legs (bonds within 30 deg of z) that cross the mid-plane of
    the layers and the sum of their tensions' z components."""
    box, atoms, bonds, l0, coeffs = data
    lx = box["x"][1] - box["x"][0]
    ly = box["y"][1] - box["y"][0]
    ea = coeffs[yarn_type]["ea"]
    zs = [a[4] for a in atoms.values() if a[1] != yarn_type]
    zmid = 0.5 * (min(zs) + max(zs))
    tensions, rsum, l0sum, legs = [], 0.0, 0.0, 0.0
    for (t, a, b) in bonds:
        if t != yarn_type:
            continue
        A, B = atoms[a], atoms[b]
        dx, dy, dz = periodic(B[2] - A[2], lx), periodic(B[3] - A[3], ly), B[4] - A[4]
        r = math.sqrt(dx * dx + dy * dy + dz * dz)
        L0 = l0[(min(a, b), max(a, b))]
        n = ea * (r - L0 * (1 - shrink)) / L0
        tensions.append(n)
        rsum += r
        l0sum += L0
        if abs(dz) > 0.866 * r and (A[4] - zmid) * (B[4] - zmid) < 0:
            legs += abs(n * dz / r)
    return {"ea": ea, "mean": sum(tensions) / len(tensions), "min": min(tensions),
            "max": max(tensions), "contraction": 1 - rsum / l0sum, "legs_fz": legs,
            "p_yarn": legs / (lx * ly), "nbonds": len(tensions)}


def stitch_verdict(stage, yt, s, plates_pressure, thickness, tl_sum):
    """One line: does the stitch hold at the end of this stage (physics)?"""
    t, ea = yt["mean"], yt["ea"]
    holds = t >= HOLD_TENSION and yt["contraction"] < s
    text = (f"- stage {STAGES.index(stage) + 1} ({stage}): yarn tension {t:.3g} N = "
            f"{t / (ea * s) * 100:.1f} % of EA s = {ea * s:.3g} N, contraction "
            f"{yt['contraction'] * 100:.1f} % of the shrink's {s * 100:.1f} %: "
            f"**{'holds' if holds else 'slack'}** (holds: at least {HOLD_TENSION:g} N and contracted "
            f"less than the shrink)")
    if stage == "release" and plates_pressure is not None:
        text += (f"; the legs press the fabric with {yt['p_yarn']:.3g} Pa, where at the end of stage 4 "
                 f"the plates added {plates_pressure:.3g} Pa to hold it at sum t_L; released, it "
                 f"swelled to {thickness / tl_sum:.3f} x sum t_L, where the mat pushes back with the "
                 f"yarn's pull alone")
    return text + "."


def layer_orientation(data, angles):
    """Length-weighted mean and standard deviation [deg] of the in-plane angle of every bond of
    each layer (bond type k = layer k) from the layer's nominal angle, wrapped to (-90, 90]."""
    box, atoms, bonds, _, _ = data
    lx = box["x"][1] - box["x"][0]
    ly = box["y"][1] - box["y"][0]
    res = {}
    for k, nominal in enumerate(angles, start=1):
        sw = swx = swxx = 0.0
        for (t, a, b) in bonds:
            if t != k:
                continue
            dx = periodic(atoms[b][2] - atoms[a][2], lx)
            dy = periodic(atoms[b][3] - atoms[a][3], ly)
            w = math.hypot(dx, dy)
            dev = (math.degrees(math.atan2(dy, dx)) - nominal) % 180.0
            if dev > 90.0:
                dev -= 180.0
            sw += w
            swx += w * dev
            swxx += w * dev * dev
        mean = swx / sw
        res[k] = (mean, math.sqrt(max(swxx / sw - mean * mean, 0.0)))
    return res


def layer_drift(before, after, nlayers):
    """Per layer: the in-plane displacement of its centroid and the RMS in-plane displacement of
    its nodes between two data files of the same atoms (unwrapped with the image flags)."""
    lx = before[0]["x"][1] - before[0]["x"][0]
    ly = before[0]["y"][1] - before[0]["y"][0]
    res = {}
    for k in range(1, nlayers + 1):
        n = sx = sy = s2 = 0.0
        for i, a in before[1].items():
            if a[1] != k or i not in after[1]:
                continue
            b = after[1][i]
            dx = (b[2] + b[5] * lx) - (a[2] + a[5] * lx)
            dy = (b[3] + b[6] * ly) - (a[3] + a[6] * ly)
            n += 1
            sx += dx
            sy += dy
            s2 += dx * dx + dy * dy
        res[k] = (math.hypot(sx / n, sy / n), math.sqrt(s2 / n))
    return res


def yarn_energy_scale(data, yarn_type, shrink):
    """The work the shrink can do: the elastic energy a yarn held at its length would store,
    EA s^2 L0 / 2 summed over the yarn's bonds [J]."""
    _, _, bonds, l0, coeffs = data
    ea = coeffs[yarn_type]["ea"]
    return sum(0.5 * ea * shrink * shrink * l0[(min(a, b), max(a, b))]
               for (t, a, b) in bonds if t == yarn_type)


def stage_rows(prefix, stage, d):
    log = os.path.join(d, f"{prefix}.{stage}.log")
    if not os.path.exists(log):
        raise ReportError(f"{log} is missing (did stage '{stage}' run?)")
    return log, [r for b in thermo_blocks(log) for r in b]


def fmt_ok(ok):
    return "ok" if ok else "**FAIL**"


def report(prefix, d, plots):
    """Markdown lines and the pass/fail of one fabric."""
    ok = True
    out = [f"## {prefix}", ""]
    summ = os.path.join(d, f"{prefix}.summary")
    dfib = float(summary_value(summ, "chain d_c, packing")[0]) * 1e-6
    tl_sum = float(summary_value(summ, "sum of t_L (compacted mat)")[0]) * 1e-3
    nlayers = sum(1 for line in open(summ) if line.startswith("layer "))
    yarn_type = nlayers + 1
    out += ["| stage | steps | wall time [s] | plate pressure at the end [Pa] | largest chain-chain "
            "penetration / d_c | kinetic energy at the end / work scale | checks |",
            "|---|---|---|---|---|---|---|"]
    curve = []    # (cumulative step, pressure, stage)
    details = []
    verdicts = []
    angles = [float(line.split()[3]) for line in open(summ) if line.strip().startswith("nominal angle, sigma")]
    sigmas = [float(line.split()[5]) for line in open(summ) if line.strip().startswith("nominal angle, sigma")]
    orient_rows = []
    compact_data = None
    for stage in STAGES:
        log, rows = stage_rows(prefix, stage, d)
        t, steps = loop_time(log)
        tag = "COMPACTION" if stage == "compact" else stage.upper()
        res = printed(log, tag)
        if res is None:
            raise ReportError(f"{log}: no {tag} line (the stage did not finish)")
        pcol = "f_plates[5]" if any("f_plates[5]" in r for r in rows) else "f_lift[5]"
        for r in rows:
            if pcol in r:
                curve.append((r["Step"], r[pcol], stage))
        p_end = rows[-1].get(pcol, 0.0) if rows else 0.0
        pen = res.get("maxpen_chain", 0.0)
        pen_ok = pen < 0.5 * dfib
        checks = [f"no pass-through {fmt_ok(pen_ok)}"]
        ok &= pen_ok
        ke = res.get("ke", 0.0)
        # the kinetic energy left at the end against the work the stage's tool does: the plate's
        # (stage 1), the needles' (stages 2 and 3: the needle work of stage 2), the shrink's
        # (stages 4 and 5: the energy the shrink would store in a yarn held at its length)
        ratio = float("nan")
        if stage == "pierce":
            needle_work = res["work"]
        if stage in ("pierce", "stitch"):
            ratio = ke / needle_work if needle_work > 0 else float("nan")
        if stage == "compact":
            ratio = res["ke_over_work"]
            gap_ok = abs(res["gap"] - res["target"]) <= 0.01 * res["target"]
            checks.append(f"gap = sum t_L {fmt_ok(gap_ok)}")
            ok &= gap_ok
        if stage in ("pretension", "release"):
            data = read_data(os.path.join(d, f"{prefix}.{stage}.data"))
            s_y = data[4][yarn_type].get("shrink", 0.0)
            escale = yarn_energy_scale(data, yarn_type, s_y)
            ratio = ke / escale if escale > 0 else float("nan")
        qs_ok = ratio < 0.01
        checks.append(f"quasi-static {fmt_ok(qs_ok)}")
        ok &= qs_ok
        if stage == "pierce":
            needles = read_needles(os.path.join(d, f"{prefix}.needles"))
            box, atoms, bonds, _, _ = read_data(os.path.join(d, f"{prefix}.pierce.data"))
            lx = box["x"][1] - box["x"][0]
            ly = box["y"][1] - box["y"][0]
            dump = read_dump(os.path.join(d, f"{prefix}.pierce.dump"))
            rneedle = 0.5 * res["needle_d"]
            node_min = needle_clearance(dump, needles, lx, ly, rneedle)
            seg_min = segment_needle_clearance(atoms, bonds, needles, lx, ly, set(range(1, yarn_type)))
            nn_ok = node_min >= rneedle
            ns_ok = seg_min >= rneedle - 0.5 * dfib
            pn_ok = res["maxpen_needle"] < 0.5 * dfib
            ok &= nn_ok and ns_ok and pn_ok
            checks.append(f"nodes out of the needles {fmt_ok(nn_ok)}")
            details += [f"- stage 2: the plate pressure fell from {rows[0][pcol]:.4g} Pa (ends held in the plane, "
                        f"end of stage 1) to {printed(log, 'PIERCE_RELEASED')['pressure']:.4g} Pa with the "
                        f"ends free in the plane, before the needles came; {len(needles)} needle(s) of "
                        f"{res['needle_d'] * 1e3:.3g} mm; at the end of the stroke the nearest fibre node is "
                        f"{node_min * 1e3:.4f} mm from a needle axis (radius {rneedle * 1e3:.3f} mm, "
                        f"{fmt_ok(nn_ok)}), the nearest fibre segment {seg_min * 1e3:.4f} mm "
                        f"({fmt_ok(ns_ok)}: more than the radius less d_c/2, i.e. the chain axis outside "
                        f"the needle's contact zone), largest needle penetration "
                        f"{res['maxpen_needle'] / dfib:.3f} d_c ({fmt_ok(pn_ok)}); needle work "
                        f"{res['work']:.3g} J, kinetic energy at the end {ke:.3g} J "
                        f"(KE / work {ke / res['work'] if res['work'] > 0 else float('nan'):.2g})."]
        if stage == "stitch":
            first = rows[0]
            f0 = first.get("c_fyarn", float("nan"))
            ins_ok = f0 == 0.0
            ok &= ins_ok
            checks.append(f"yarn inserted without overlap {fmt_ok(ins_ok)}")
            details.append(f"- stage 3: {int(res['yarn_nodes'])} yarn nodes added; largest contact force "
                           f"on a yarn node at insertion {f0:.3g} N ({fmt_ok(ins_ok)}: zero means no "
                           f"overlap); needles out after {int(res['nstroke'])} steps.")
        if stage in ("pretension", "release"):
            s = s_y
            yt = yarn_tension(data, yarn_type, s)
            model = yt["ea"] * (s - yt["contraction"])
            # (the stages print -compute bond/local's force, i.e. a tension)
            lam = res["yarn_tension_mean"]
            t_ok = abs(lam - yt["mean"]) <= 1e-6 * max(abs(yt["mean"]), 1e-12) + 1e-9 * yt["ea"]
            m_ok = abs(model - yt["mean"]) <= 0.02 * yt["ea"] * s
            ok &= t_ok and m_ok
            checks.append(f"yarn tension {fmt_ok(t_ok and m_ok)}")
            details.append(
                f"- stage {STAGES.index(stage) + 1}: yarn shrink s = {s:.4g}; the yarn contracted by "
                f"{yt['contraction'] * 100:.2f} % of its reference length, so the rod model gives a mean "
                f"tension EA (s - contraction) = {model:.4g} N (EA = {yt['ea']:.4g} N); from the data "
                f"file, bond by bond: {yt['mean']:.4g} N (min {yt['min']:.3g}, max {yt['max']:.3g}; "
                f"{fmt_ok(m_ok)} within 2 % of EA s), LAMMPS compute bond/local: {lam:.4g} N ({fmt_ok(t_ok)}); "
                f"the legs crossing the mid-plane pull the faces together with {yt['legs_fz']:.4g} N, "
                f"a pressure of {yt['p_yarn']:.4g} Pa on the RVE.")
            pre = printed(os.path.join(d, f"{prefix}.pretension.log"), "PRETENSION")
            verdicts.append(stitch_verdict(stage, yt, s, pre.get("pressure_upper") if pre else None,
                                           res.get("thickness"), tl_sum))
            if stage == "release":
                thick, vf = res["thickness"], res["vf"]
                fmax = res["fmax"]
                fref = yt["ea"] * s    # the tension of a yarn held at its length
                bal_ok = fmax < 1e-2 * fref
                pbc_ok = abs(res["pbc"]) < 1e-12
                ok &= bal_ok and pbc_ok
                checks.append(f"equilibrium {fmt_ok(bal_ok)}")
                details.append(
                    f"- stage 5, as manufactured: layer thickness {thick * 1e3:.4f} mm against "
                    f"sum t_L = {tl_sum * 1e3:.4f} mm ({thick / tl_sum:.3f} x), fibre volume fraction "
                    f"{vf:.3f}; largest force on a node {fmax:.3g} N = {fmax / fref:.2g} of EA s, the "
                    f"tension of a yarn held at its length ({fmt_ok(bal_ok)}: below 1 %); averaged PBC violation "
                    f"{res['pbc']:.3g} m ({fmt_ok(pbc_ok)}); the plate pressure when the upper plate "
                    f"had lifted: {printed(log, 'RELEASE_LIFTED')['pressure']:.3g} Pa.")
        sdata = read_data(os.path.join(d, f"{prefix}.{stage}.data"))
        if stage == "compact":
            compact_data = sdata
        ori = layer_orientation(sdata, angles)
        drift = layer_drift(compact_data, sdata, nlayers)
        orient_rows.append(f"| {TITLES[stage]} | " + " | ".join(
            f"{ori[k][0]:+.2f} / {ori[k][1]:.2f} | {drift[k][0] * 1e3:.4f} / {drift[k][1] * 1e3:.4f}"
            for k in range(1, nlayers + 1)) + " |")
        out.append(f"| {TITLES[stage]} | {steps} | {t:.1f} | {p_end:.4g} | {pen / dfib:.3f} | "
                   f"{ratio:.2g} | {', '.join(checks)} |")
    out.append("")
    out += details
    if verdicts:
        out += ["", "Does the stitch hold? (physics, not a code check: the yarn against EA s, the pressure "
                "of its legs on the fabric)", ""] + verdicts
    out += ["", "Orientation of the layers' segments (length-weighted deviation from the nominal angle, "
            "mean / SD in degrees; generated with sampled SD " + ", ".join(f"{x:g}" for x in sigmas) +
            " deg) and how far the layers moved in the plane since the end of stage 1 (centroid / RMS "
            "of the nodes, mm):", "",
            "| stage | " + " | ".join(f"layer {k} ({angles[k - 1]:g} deg): orientation | layer {k}: drift"
                                      for k in range(1, nlayers + 1)) + " |",
            "|---|" + "---|---|" * nlayers] + orient_rows
    out.append("")
    if plots:
        try:
            import matplotlib
            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
            fig, ax = plt.subplots(figsize=(6.5, 3.6))
            for stage in STAGES:
                pts = [(s, p) for (s, p, st) in curve if st == stage]
                if pts:
                    ax.plot([s for s, _ in pts], [max(p, 1.0) for _, p in pts], label=TITLES[stage])
            ax.set_yscale("log")
            ax.set_xlabel("step")
            ax.set_ylabel("upper plate pressure [Pa]")
            ax.set_title(f"{prefix}: pressure on the upper plate through the stages")
            ax.legend(fontsize=8)
            fig.tight_layout()
            png = os.path.join(d, f"{prefix}.pressure.png")
            fig.savefig(png, dpi=110)
            out.append(f"![{prefix} plate pressure]({os.path.basename(png)})")
            out.append("")
        except ImportError:
            out.append("(matplotlib missing: no pressure curve)")
    return out, ok


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("prefixes", nargs="+")
    ap.add_argument("--dir", default=".")
    ap.add_argument("--out", default=None)
    ap.add_argument("--no-plots", action="store_true")
    a = ap.parse_args()
    lines, ok = [], True
    try:
        for p in a.prefixes:
            l, o = report(p, a.dir, not a.no_plots)
            lines += l
            ok &= o
    except (ReportError, OSError, KeyError) as e:
        print(f"report_manufacturing.py: ERROR: {e}", file=sys.stderr)
        return 1
    lines.append("Result: " + ("PASS" if ok else "FAIL"))
    text = "\n".join(lines) + "\n"
    if a.out:
        with open(a.out, "w") as f:
            f.write(text)
    print(text)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
