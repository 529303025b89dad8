#!/usr/bin/env python3
"""Planted-bug audit of the USER-NCF tests (mutation testing by hand-written mutations).

Each mutation below is one plausible one-line bug in a style or kernel: the file, the exact
original text (it must occur exactly once), its replacement, and the ctest regex of the tests that
should catch it. For every mutation the script puts the bug into the source tree, rebuilds the
plugin and the test executables of that regex incrementally (ninja: only what depends on the
file), runs those tests one at a time (unit before integration before mpi) up to the first
failure, and puts the original back. A mutation is KILLED when a test fails or times out,
SURVIVED when all pass, BUILD-ERROR when the mutated code does not compile (then the mutation
itself is at fault).

The original file is always put back: in a `finally` block (also on Ctrl-C and SIGTERM), and a
copy of it is kept under <build>/mutation-audit/backup while it is mutated, which the next start
of the script puts back first if a previous run was killed outright.

Usage (from anywhere; nice it, it takes a while):
  nice -n 15 /usr/bin/python3 tests/mutation_audit.py [--build DIR] [-j N] [--only ID,ID]
                                                      [--list] [--check] [--baseline] [--timeout S]
  --build     the build folder (default $NCF_BUILD, else ./build); configured by tools/setup.sh
  --only      run these mutations only (ids, comma separated)
  --list      print the mutations and exit
  --check     check that every mutation applies (its original text occurs exactly once) and exit;
              a test of the suite (unit.mutation_audit_applies), so that the audit follows the code
  --baseline  first run all the regexes without a mutation (they must pass)
  --timeout   seconds one test may run under a mutation (default 300; a hang counts as killed,
              as the test's own ctest TIMEOUT would fail it)
Results: printed, and written to <build>/mutation-audit/results.txt (one line per mutation, then
the summary); the logs of the builds and tests of each mutation under <build>/mutation-audit/.
Exit status 0 when every mutation was killed, 1 otherwise.
"""

import argparse
import os
import re
import shutil
import signal
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SRC = "src/USER-NCF/"

# (id, file, original, replacement, ctest regex, what the bug is)
M = []


def mut(mid, path, old, new, tests, what):
    M.append(dict(id=mid, path=path if "/" in path else SRC + path, old=old, new=new, tests=tests,
                  what=what))


BOND = r"^(integration\.test_bond_chain|mpi\.test_bond_chain_mpi|integration\.test_compaction|integration\.test_split_runs)$"
ORIENT = r"^(unit\.test_orient|integration\.test_compute_orient)$"
PBC = r"^(unit\.test_pbc|integration\.test_fix_pbc|integration\.test_split_runs|mpi\.test_fix_pbc_mpi)$"
PLATE = r"^(unit\.test_wall|integration\.test_fix_plate|integration\.test_split_runs|mpi\.test_fix_plate_mpi)$"
NEEDLE = r"^(unit\.test_needle|integration\.test_fix_needles|integration\.test_split_runs|mpi\.test_fix_needles_mpi)$"
SHRINK = r"^(integration\.test_fix_shrink|integration\.test_split_runs)$"
CONTACT = (r"^(unit\.test_contact.*|integration\.test_pair_contact.*|integration\.test_split_runs"
           r"|mpi\.test_pair_contact_ranks|mpi\.test_pair_contact_peratom_mpi|mpi\.test_split_runs_mpi"
           r"|harness\.pair\..*)$")
GEOM = r"^(unit\.test_geometry|unit\.test_contact_core|integration\.test_pair_contact_list)$"

# ---------------------------------------------------------------- bond_style ncf/chain
mut("bond-length-2d", "bond_ncf_chain.cpp",
    "const double r = sqrt(delx * delx + dely * dely + delz * delz);",
    "const double r = sqrt(delx * delx + dely * dely);", BOND, "bond length without its z part")
mut("bond-force-sign", "bond_ncf_chain.cpp", "f[i2][0] -= delx * fbond;", "f[i2][0] += delx * fbond;",
    BOND, "force on the second atom with the wrong sign (x)")
mut("bond-ghost-force", "bond_ncf_chain.cpp", "if (newton_bond || i2 < nlocal) {",
    "if (i2 < nlocal) {", BOND, "newton on: the force on a ghost partner dropped")
mut("bond-capture-sign", "bond_ncf_chain.cpp", "store_slot(i2, -d, r);", "store_slot(i2, d, r);",
    BOND, "captured L0 stored under the wrong relative tag on the partner")
mut("bond-capture-comm", "bond_ncf_chain.cpp",
    "comm->reverse_comm(this);    // ghost slots filled here go to their owners",
    "// (reverse communication of the captured slots dropped)", BOND,
    "captured L0 of ghost atoms not sent to their owners")
mut("bond-lookup-partner", "bond_ncf_chain.cpp", "if (dtag[j][k] == -d) return l0[j][k];",
    "if (dtag[j][k] == d) return l0[j][k];", BOND, "L0 looked up in the partner's slots with the wrong sign")
mut("bond-dt-factor", "bond_ncf_chain.cpp", "omega2 = std::max(omega2, 2.0 * ksum[i] / m);",
    "omega2 = std::max(omega2, ksum[i] / m);", BOND, "critical time step off by sqrt(2)")
mut("bond-area-factor", "bond_ncf_chain.cpp", "ea_in = modulus * 0.25 * M_PI * diameter * diameter;",
    "ea_in = modulus * M_PI * diameter * diameter;", BOND, "EA from the diameter as if it were the radius")
mut("rod-compression-side", "ncf_rod.h", "const double kk = select_bits(dr < 0.0, s.kc, s.k);",
    "const double kk = select_bits(dr > 0.0, s.kc, s.k);", r"^(unit\.test_rod|integration\.test_bond_chain)$",
    "compression ratio applied in tension")
mut("bond-restart-shrink", "bond_ncf_chain.cpp",
    "  MPI_Bcast(&shrink[1], n, MPI_DOUBLE, 0, world);\n", "", BOND + "|^integration\\.test_split_runs$",
    "shrink factors of a restart file not broadcast from rank 0")

# ---------------------------------------------------------------- compute ncf/orient
mut("orient-closest-image", "compute_ncf_orient.cpp", "      j = domain->closest_image(i, j);\n", "",
    ORIENT, "bond partner not taken at its closest periodic image")
mut("orient-newton-off", "compute_ncf_orient.cpp", "if (!newton_bond && partner < tag[i]) continue;",
    "if (!newton_bond && partner < 0) continue;", ORIENT, "newton_bond off: every bond counted twice")
mut("orient-fold-upper", "ncf_orient.cpp", "if (d > 90.0) d -= 180.0;", "if (d > 270.0) d -= 180.0;",
    ORIENT, "deviations past +90 deg not folded")
mut("orient-output-4", "compute_ncf_orient.cpp", "v[3] = s.principal_value();",
    "v[3] = s.outside_fraction();", ORIENT, "output 4 (principal value) from the wrong statistic")
mut("orient-output-5", "compute_ncf_orient.cpp", "v[4] = s.outside_fraction();",
    "v[4] = 1.0 - s.outside_fraction();", ORIENT, "output 5 (share outside the range) inverted")
mut("orient-output-6", "compute_ncf_orient.cpp", "v[5] = s.weight();", "v[5] = s.principal_value();",
    ORIENT, "output 6 (weight) from the wrong statistic")

# ---------------------------------------------------------------- fix ncf/pbc
mut("pbc-restart-box", "fix_ncf_pbc.cpp", "for (int k = 0; k < 6; k++) href[k] = buf[m++];",
    "for (int k = 0; k < 6; k++) href[k] = domain->h[k] + 0.0 * buf[m++];", PBC,
    "restart: the reference box taken from the current (deformed) box")
mut("pbc-predict-force", "fix_ncf_pbc.cpp", "pred[d] = xu[d] + dt * v[i][d] + dt2 * f[i][d] / m;",
    "pred[d] = xu[d] + dt * v[i][d];", PBC, "predicted position without the force")
mut("pbc-mass-weight", "fix_ncf_pbc.cpp", "s[6] += e.weight * e.weight / m;", "s[6] += e.weight / m;", PBC,
    "multiplier with the wrong weight")
mut("pbc-shear", "fix_ncf_pbc.cpp",
    "const double target[3] = {F[0][0] * D[0] + F[0][1] * D[1], F[1][1] * D[1], D[2]};",
    "const double target[3] = {F[0][0] * D[0], F[1][1] * D[1], D[2]};", PBC, "shear of the box ignored")
mut("pbc-setup-lambda", "fix_ncf_pbc.cpp",
    "} else if (lambda_step == update->ntimestep && lambda_last.size() == lambda.size()) {",
    "} else if (false) {", PBC, "a run's setup does not apply the multipliers of the step before")
mut("pbc-restart-lambda-step", "fix_ncf_pbc.cpp", "    lambda_step = (bigint) buf[m++];",
    "    lambda_step = (bigint) buf[m++] - 1;", PBC, "restart: the step of the stored multipliers off by one")
mut("pbc-min-sign", "fix_ncf_pbc.cpp",
    "      f[i][d] += e.weight * lam;", "      f[i][d] -= e.weight * lam;", PBC,
    "minimisation: projection with the wrong sign")
mut("pbc-weights-index", "ncf_pbc.cpp",
    "w[i] = nodes[i].side < 0 ? -1.0 / nlow[group[i]] : 1.0 / nup[group[i]];",
    "w[i] = nodes[i].side < 0 ? -1.0 / nup[group[i]] : 1.0 / nup[group[i]];", PBC,
    "lower-face weights from the upper face's count")
mut("pbc-allreduce", "fix_ncf_pbc.cpp",
    "  MPI_Allreduce(work.data(), sums.data(), (int) work.size(), MPI_DOUBLE, MPI_SUM, world);\n\n"
    "  // targets F D_g",
    "  sums = work;\n\n  // targets F D_g", PBC, "group sums not summed over the ranks")

# ---------------------------------------------------------------- fix ncf/plate, motion, clock
mut("plate-velocity-sign", "fix_ncf_plate.cpp",
    "NCF::plane_contact(x[i][2], radius, p.z, side, cc.kn, l, cc.damp, v[i][2] - p.vz);",
    "NCF::plane_contact(x[i][2], radius, p.z, side, cc.kn, l, cc.damp, v[i][2] + p.vz);", PLATE,
    "dashpot with the plate's velocity added instead of subtracted")
mut("motion-target-direction", "ncf_motion.h", "        v = dir * speed;", "        v = speed;",
    PLATE + "|" + NEEDLE, "target motion: the velocity without the direction")
mut("wall-damp-sign", "ncf_wall.h", "double f = elastic - damp * length * side * vn_rel;",
    "double f = elastic + damp * length * side * vn_rel;", PLATE, "plate dashpot with the wrong sign")
mut("plate-tributary", "fix_ncf_plate.cpp", "return 0.5 * (l0[i][0] + l0[i][1]);",
    "return l0[i][0] + l0[i][1];", PLATE, "tributary length twice too long")
mut("plate-pressure-index", "fix_ncf_plate.cpp", "      return totals[0][0] / area;",
    "      return totals[1][0] / area;", PLATE, "output 6 (lower pressure) from the upper plate")
mut("plate-restart-clock", "fix_ncf_plate.cpp", "    clock.unpack(&buf[11]);\n",
    "    clock.start(update);\n", PLATE, "restart: the plate's clock starts anew")
mut("plate-penmax-reduce", "fix_ncf_plate.cpp", "MPI_Allreduce(pen, penall, 2, MPI_DOUBLE, MPI_MAX, world);",
    "MPI_Allreduce(pen, penall, 2, MPI_DOUBLE, MPI_SUM, world);", PLATE,
    "largest penetration summed over the ranks")
mut("clock-off-by-one", "lammps_ncf_clock.h",
    "const double t = base + (double) (u->ntimestep - step_base) * u->dt;",
    "const double t = base + (double) (u->ntimestep - step_base + 1) * u->dt;", PLATE + "|" + NEEDLE,
    "tool clock one step ahead")
mut("clock-pack-step", "lammps_ncf_clock.h", "    buf[2] = (double) step_base;\n",
    "    buf[2] = 0.0;\n", PLATE + "|" + NEEDLE, "restart: the clock's base step not written")

# ---------------------------------------------------------------- fix ncf/needles
mut("needles-energy-half", "fix_ncf_needles.cpp", "emine += 0.5 * c.energy;", "emine += c.energy;",
    NEEDLE, "needle energy counted from both nodes in full")
mut("needles-restart-clock", "fix_ncf_needles.cpp", "    clock.unpack(&buf[5]);\n",
    "    clock.start(update);\n", NEEDLE, "restart: the needles' clock starts anew")
mut("needles-radius", "fix_ncf_needles.cpp", "const double rc = 0.25 * (di + dj);",
    "const double rc = 0.5 * (di + dj);", NEEDLE, "chain radius from the diameters twice too large")
mut("needles-image", "fix_ncf_needles.cpp",
    "  NCF_COMPAT::minimum_image(domain, FLERR, d[0], d[1], d[2]);\n  if (d[0] * d[0]",
    "  if (d[0] * d[0]", NEEDLE,
    "needle not taken at its closest periodic image")
mut("needles-reaction-sign", "fix_ncf_needles.cpp", "local[3 * k + 1] -= c.f[0].y;",
    "local[3 * k + 1] += c.f[0].y;", NEEDLE, "force on the needle (y) with the wrong sign")
mut("needles-count", "fix_ncf_needles.cpp", "ncontact = (int) std::lround(all[3 * nn + 1] / 2.0);",
    "ncontact = (int) std::lround(all[3 * nn + 1]);", NEEDLE, "contacts counted from both nodes")
mut("needles-near-reach", "fix_ncf_needles.cpp",
    "const double reach = half + radius + 0.5 * dmax_chain;",
    "const double reach = half + 0.5 * dmax_chain;", NEEDLE,
    "the grid of the cells near a needle flags too few cells (needle radius left out)")
mut("needles-partners-stale", "fix_ncf_needles.cpp", "neighbor->ncalls != part_ncalls ||",
    "false ||", NEEDLE, "bond partners of the needle fix not looked up again after reneighbouring")
mut("needle-profile-slope", "ncf_needle.cpp", "drho_du = (lower ? 1.0 : -1.0) * n.radius / n.tip * dphi;",
    "drho_du = n.radius / n.tip * dphi;", NEEDLE, "slope of the needle's far taper with the wrong sign")

# ---------------------------------------------------------------- fix ncf/shrink
mut("shrink-start", "fix_ncf_shrink.cpp", "current = start + (target - start) * ramp(shape, tau);",
    "current = target * ramp(shape, tau);", SHRINK, "ramp from 0 instead of the starting shrink")
mut("shrink-cosine", "fix_ncf_shrink.cpp", "return shape == COSINE ? 0.5 * (1.0 - cos(M_PI * tau)) : tau;",
    "return shape == COSINE ? 0.5 * (1.0 + cos(M_PI * tau)) : tau;", SHRINK, "cosine ramp upside down")
mut("shrink-restart-step0", "fix_ncf_shrink.cpp", "  step0 = (bigint) buf[3];\n", "", SHRINK,
    "restart: the ramp's first step not read")
mut("shrink-thermal-sign", "fix_ncf_shrink.cpp", "target = -alpha * dT;", "target = alpha * dT;", SHRINK,
    "thermal strain with the wrong sign")

# ---------------------------------------------------------------- pair ncf/contact and its kernels
mut("friction-slip-sign", "ncf_contact.cpp", "    slip += dt * vt;\n", "    slip -= dt * vt;\n", CONTACT,
    "slip accumulated against the relative velocity")
mut("friction-cap", "ncf_contact.cpp", "const double fm2 = norm2(f), cap = mu * fn;",
    "const double fm2 = norm2(f), cap = fn;", CONTACT, "Coulomb limit without mu")
mut("tangential-reaction", "ncf_contact.cpp", "  c.f[3] -= c.t * ftot;\n", "  c.f[3] += c.t * ftot;\n",
    CONTACT, "tangential force on B1 with the wrong sign")
mut("contact-dt-factor", "pair_ncf_contact.cpp", "omega2 = MAX(omega2, 2.0 * knmax * len / m);",
    "omega2 = MAX(omega2, knmax * len / m);", CONTACT, "critical time step of the contacts off by sqrt(2)")
mut("list-key-order", "pair_ncf_contact_list.cpp",
    "return (b.k0 > ta) | ((b.k0 == ta) & (b.k1 > tpa));", "return (b.k0 != ta) | (b.k1 != tpa);",
    CONTACT, "segment pairs listed from both segments (double counting)")
mut("list-image", "pair_ncf_contact_list.cpp", "int q = (m < 0) ? -2 : domain->closest_image(k, m);",
    "int q = (m < 0) ? -2 : m;", CONTACT, "chain partner not taken at its closest periodic image")
mut("list-skin", "pair_ncf_contact_list.cpp", "if (gap >= grow * skin) return;",
    "if (gap >= grow * 0.5 * skin) return;", CONTACT, "pairs that can close within the skin dropped")
mut("endcap-length", "pair_ncf_contact_list.cpp",
    "if (cnb[k][0] != 0.0 && cnb[k][1] == 0.0) endext[k] = endcap_frac * table.diameter(type[k]);",
    "if (cnb[k][0] != 0.0 && cnb[k][1] == 0.0) endext[k] = 0.5 * endcap_frac * table.diameter(type[k]);",
    CONTACT, "end caps half as long as the setting")
mut("virtual-reaction", "pair_ncf_contact_compute.cpp", "        fj[d] -= g[d];\n", "        fj[d] += g[d];\n",
    CONTACT, "end-cap force mapped onto the neighbour with the wrong sign")
mut("fatom-reverse-comm", "pair_ncf_contact_compute.cpp",
    "    comm_mode = COMM_FORCE;\n    comm->reverse_comm(this);\n", "    comm_mode = COMM_FORCE;\n", CONTACT,
    "per-atom contact force of ghosts not sent back to the owners")
mut("fatom-unpack", "pair_ncf_contact_compute.cpp", "    fcon[3 * j] += buf[m++];\n",
    "    fcon[3 * j] = buf[m++];\n", CONTACT, "per-atom contact force from ghosts overwrites (x)")
mut("mix-kn", "ncf_contact_model.cpp", "c.kn = 2.0 * ii.kn * jj.kn / (ii.kn + jj.kn);",
    "c.kn = 0.5 * (ii.kn + jj.kn);", CONTACT, "mixed kn: arithmetic mean, not in series")
mut("kt-ratio", "ncf_contact_model.h", "double kt_stiffness() const { return kt * kn; }",
    "double kt_stiffness() const { return kt; }", CONTACT,
    "kt taken as a stiffness, not as a ratio of kn")
mut("ghost-shell-history", "pair_ncf_contact.cpp", "(use_history ? 3.0 : 2.0) * lmax_used;",
    "(use_history ? 2.0 : 2.0) * lmax_used;", CONTACT, "ghost shell without the take-over lmax")
mut("cap-force-sign", "pair_ncf_contact_compute.cpp", "        f[ids[m]][1] += c.f[m].y;\n",
    "        f[ids[m]][1] -= c.f[m].y;\n", CONTACT, "node-cap force with the wrong sign (y)")
mut("skin-check", "pair_ncf_contact_compute.cpp",
    "if (dmove2 > 0.25 * neighbor->skin * neighbor->skin * (1.0 + 1e-9))",
    "if (dmove2 > 1.0 * neighbor->skin * neighbor->skin * (1.0 + 1e-9))", CONTACT,
    "moves up to the full skin allowed between list builds")
mut("tangential-setup-advance", "pair_ncf_contact_compute.cpp",
    "espring = NCF::contact_tangential(c, vel, sv, tp.kt, tp.mu, tp.damp, s.dt, s.advance);",
    "espring = NCF::contact_tangential(c, vel, sv, tp.kt, tp.mu, tp.damp, s.dt, true);", CONTACT,
    "friction history advanced in a run's setup")
mut("history-takeover", "pair_ncf_contact_history.cpp",
    "  if (p) cand[nc][0] = A, cand[nc++][1] = make_key(b1, p);\n", "", CONTACT,
    "take-over of the slip of the pair one segment further along B (past B1) dropped")
mut("history-defer", "pair_ncf_contact_history.cpp", "if (m >= atom->nlocal && local_only) return false;",
    "if (false && local_only) return false;", CONTACT,
    "take-over from a ghost's row not deferred until the rows are communicated")
mut("history-rows-needed", "pair_ncf_contact_history.cpp",
    "if (j >= 0 && j != nodes[k ^ 1]) mark_lower(nodes[k], j);",
    "if (j >= 0 && j != nodes[k ^ 1] && k >= 2) mark_lower(nodes[k], j);", CONTACT,
    "history rows of the segments next to A not flagged for the take-overs: not communicated")
mut("history-rows-owner", "pair_ncf_contact_history.cpp", "  comm->reverse_comm(this, 1);\n", "",
    CONTACT, "the flags of the history rows a take-over needs not summed onto their owners")
mut("history-exchange", "fix_ncf_contact_history.cpp",
    "  if (NCFContactHistoryOwner *p = owner()) p->sync_history();\n", "", CONTACT,
    "friction history not written to the per-atom store before atoms migrate")
mut("history-restart-step", "fix_ncf_contact_history.cpp",
    "if (update->ntimestep == output->next_restart) pre_exchange();",
    "if (update->ntimestep == output->next_restart + 1) pre_exchange();", CONTACT,
    "restart file written during a run without the history of its step")
mut("batch-spring-energy", "ncf_contact_batch.cpp",
    "const double energy = 0.5 * (fx * fx + fy * fy + fz * fz) / kts;",
    "const double energy = (fx * fx + fy * fy + fz * fz) / kts;", CONTACT,
    "batched slip-spring energy twice too large")
mut("closest-t-sign", "ncf_geometry.h", "        t = (b * s + f) / e;\n", "        t = (b * s - f) / e;\n",
    GEOM, "closest point on the second segment with the wrong sign")


# ---------------------------------------------------------------- fix ncf/damp
DAMP = r"^(integration\.test_split_runs|mpi\.test_split_runs_mpi|examples\.manufacturing)$"
mut("damp-setup-fullstep", "fix_ncf_damp.cpp", "      drag(i, kept[i]);", "      drag(i, v[i]);", DAMP,
    "the setup's drag from the full-step velocity (fix viscous's behaviour)")
mut("damp-restart-lost", "fix_ncf_damp.cpp", "for (int d = 0; d < NKEEP; d++) buf[d + 1] = kept[i][d];",
    "for (int d = 0; d < NKEEP; d++) buf[d + 1] = -1.0;", DAMP,
    "the kept velocities and their step not written to the restart file")
mut("damp-exchange-lost", "fix_ncf_damp.cpp", "for (int d = 0; d < NKEEP; d++) buf[d] = kept[i][d];",
    "for (int d = 0; d < NKEEP; d++) buf[d] = -1.0;", DAMP,
    "the kept velocities not migrating with their atom to another rank")

# ---------------------------------------------------------------- bond ncf/chain's cache
mut("bond-l0-cache-stale", "bond_ncf_chain.cpp",
    "if (l0_ncalls != neighbor->ncalls || (int) l0_list.size() != nbondlist) {",
    "if ((int) l0_list.size() != nbondlist) {",
    BOND,
    "reference lengths of the bond list not looked up again after the list was rebuilt")

# ---------------------------------------------------------------- command ncf/check
CHECK = r"^(integration\.test_bad_input|integration\.bad_input_scripts)$"
mut("check-ge-strict", "command_ncf_check.cpp", "ok = v >= b;", "ok = v > b;", CHECK,
    "a bound '>=' checked as '>' (the bound itself refused)")

# ---------------------------------------------------------------- tools
GEN = r"^(unit\.test_gen|unit\.test_bad_cards|integration\.test_gen_lammps|examples\.gen-.*)$"
mut("gen-sigma-dropped", "tools/ncf-gen/ncf_gen_build.cpp", "for (auto &d : dev) d *= spec.sigma;",
    "for (auto &d : dev) d *= 0.5 * spec.sigma;", GEN,
    "the chain angles drawn with half the card's SD")
MEASURE = r"^(unit\.ncf_measure)$"
mut("measure-unweighted-mean", "tools/ncf-measure/ncf_measure.py", "m = np.sum(w * x) / W",
    "m = np.mean(x)", MEASURE, "orientation mean not weighted by the segment lengths")
mut("measure-wrap-360", "tools/ncf-measure/ncf_measure.py",
    "return 90.0 - np.mod(90.0 - np.asarray(a, dtype=float), 180.0)",
    "return 180.0 - np.mod(180.0 - np.asarray(a, dtype=float), 360.0)", MEASURE,
    "deviations wrapped as directions (360 deg), not as axes (180 deg)")
EXPORT = r"^(unit\.perm_ncf_export)$"
mut("export-packing-dropped", "tools/ncf-export/ncf_export.py",
    "frac = ins.sum(axis=2) / S * pack[kk][:, None]", "frac = ins.sum(axis=2) / S",
    EXPORT, "the voxel's fibre fraction without the chain's packing")
mut("export-volume-packing", "tools/ncf-export/ncf_export.py",
    "return float(np.sum(L * math.pi * r * r * p))", "return float(np.sum(L * math.pi * r * r))",
    EXPORT, "the chains' fibre volume (the voxels' check) without the packing")
PERM = r"^(unit\.perm_solver|unit\.perm_ncf_perm)$"
mut("perm-gebart-parallel", "tools/ncf-perm/ncf_perm_solver.cpp",
    "std::min(bsolid, 1.0 / gebart_parallel(v, o.fibre_radius, o.packing));",
    "std::min(bsolid, 1.0 / gebart_perpendicular(v, o.fibre_radius, o.packing));", PERM,
    "Gebart's perpendicular permeability along the fibres too")


# ---------------------------------------------------------------- machinery
class Restore:
    """The original text of the mutated file, put back whatever happens."""

    def __init__(self, path, backup):
        self.path, self.backup = path, backup
        with open(path) as f:
            self.text = f.read()
        os.makedirs(os.path.dirname(backup), exist_ok=True)
        shutil.copy2(path, backup)

    def put_back(self):
        with open(self.path, "w") as f:
            f.write(self.text)
        os.remove(self.backup)


def restore_leftovers(backup_root):
    """Put back files left mutated by a run that was killed outright."""
    if not os.path.isdir(backup_root):
        return
    for dirpath, _, files in os.walk(backup_root):
        for name in files:
            b = os.path.join(dirpath, name)
            rel = os.path.relpath(b, backup_root)
            print(f"[audit] restoring {rel} left mutated by an interrupted run")
            shutil.copy2(b, os.path.join(ROOT, rel))
            os.remove(b)


def ctest_names(build, regex):
    out = subprocess.run(["ctest", "-N", "-R", regex], cwd=build, capture_output=True, text=True).stdout
    return re.findall(r"Test\s+#\d+: (\S+)", out)


def targets_for(names):
    t = ["ncfplugin"]
    for n in names:
        kind, _, rest = n.partition(".")
        if kind in ("unit", "integration", "mpi") and rest.startswith("test_"):
            t.append(f"{kind}_{rest}")
    return t


def run(cmd, cwd, log, timeout):
    """Runs cmd in a session of its own; on a timeout or an interrupt the whole session (ctest,
    mpiexec and its ranks) is killed, not only its leader."""
    with open(log, "w") as f:
        p = subprocess.Popen(cmd, cwd=cwd, stdout=f, stderr=subprocess.STDOUT, start_new_session=True)
        try:
            return p.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            f.write(f"\n[audit] timed out after {timeout} s\n")
            return 124
        finally:
            if p.poll() is None:
                for sig in (signal.SIGTERM, signal.SIGKILL):
                    try:
                        os.killpg(p.pid, sig)
                    except ProcessLookupError:
                        break
                    try:
                        p.wait(timeout=10)
                        break
                    except subprocess.TimeoutExpired:
                        pass


def failed_tests(log):
    """The ctest tests that failed, each with the GoogleTest cases that failed in it."""
    with open(log, errors="replace") as f:
        text = re.sub(r"\x1b\[[0-9;]*m", "", f.read())    # (GoogleTest colours under mpirun)
    tests = re.findall(r"\d+ - (\S+) \((?:Failed|Timeout|SEGFAULT|Subprocess aborted|Exception)[^)]*\)", text)
    cases = sorted(set(re.findall(r"^\[  FAILED  \] (\w[\w/.]*\.\w[\w/]*)(?: \(\d+ ms\))?$", text, re.M)))
    if "Timeout" in text and re.search(r"\(Timeout\)", text):
        cases.append("(timeout)")
    return [t + (f"[{','.join(cases)}]" if cases else "") for t in tests]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.environ.get("NCF_BUILD", os.path.join(ROOT, "build")))
    ap.add_argument("-j", type=int, default=2)
    ap.add_argument("--only", default="")
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--baseline", action="store_true")
    ap.add_argument("--timeout", type=int, default=300,
                    help="seconds one test may run under a mutation (a hang counts as killed)")
    args = ap.parse_args()

    chosen = M
    if args.only:
        ids = args.only.split(",")
        unknown = [i for i in ids if i not in {m["id"] for m in M}]
        if unknown:
            sys.exit(f"unknown mutation id(s): {', '.join(unknown)}")
        chosen = [m for m in M if m["id"] in ids]
    if args.list:
        for m in chosen:
            print(f"{m['id']:28s} {m['path']:42s} {m['what']}")
        print(f"{len(chosen)} mutations")
        return 0

    # every mutation must apply to exactly one place before anything starts
    stale = []
    for m in chosen:
        path = os.path.join(ROOT, m["path"])
        n = 0
        if os.path.isfile(path):
            with open(path) as f:
                n = f.read().count(m["old"])
        if n != 1:
            stale.append(f"mutation {m['id']}: the original text occurs {n} times in {m['path']}")
    if stale:
        sys.exit("\n".join(stale))
    if args.check:
        print(f"{len(chosen)} mutations, each applies to exactly one place")
        return 0

    build = os.path.abspath(args.build)
    if not os.path.isfile(os.path.join(build, "CTestTestfile.cmake")):
        sys.exit(f"{build} is not a configured build folder (run tools/setup.sh)")
    work = os.path.join(build, "mutation-audit")
    backup_root = os.path.join(work, "backup")
    restore_leftovers(backup_root)
    os.makedirs(work, exist_ok=True)

    # SIGTERM like Ctrl-C: the finally blocks put the files back
    def on_term(signum, frame):
        raise KeyboardInterrupt

    signal.signal(signal.SIGTERM, on_term)

    def build_and_test(regex, tag, everything=False):
        names = ctest_names(build, regex)
        if not names:
            raise SystemExit(f"{tag}: no test matches {regex}")
        blog, tlog = os.path.join(work, tag + ".build.log"), os.path.join(work, tag + ".test.log")
        # (a tool's source: the whole build, incremental, since the tools' targets are their own)
        targets = [] if everything else ["--target"] + targets_for(names)
        if run(["cmake", "--build", build, "-j", str(args.j)] + targets, ROOT, blog, 3600) != 0:
            return "BUILD-ERROR", [], names
        # one test at a time, the quick suites first, up to the first failure (ctest itself would
        # start with the longest)
        rank = {"unit": 0, "integration": 1, "mpi": 2}
        for n in sorted(names, key=lambda n: (rank.get(n.split(".")[0], 3), n)):
            rc = run(["ctest", "-R", "^" + re.escape(n) + "$", "-j1", "--output-on-failure"], build, tlog,
                     args.timeout)
            if rc == 124:
                return "FAILED", [n + "[timeout]"], names
            if rc != 0:
                return "FAILED", failed_tests(tlog) or [n], names
        return "PASSED", [], names

    if args.baseline:
        regex = "|".join(sorted({m["tests"] for m in chosen}))
        state, failed, names = build_and_test(regex, "baseline", True)
        print(f"[audit] baseline ({len(names)} tests): {state} {' '.join(failed)}", flush=True)
        if state != "PASSED":
            sys.exit("[audit] the tests must pass without a mutation")

    results = []
    t_all = time.time()
    try:
        for k, m in enumerate(chosen):
            path = os.path.join(ROOT, m["path"])
            guard = Restore(path, os.path.join(backup_root, m["path"]))
            t0 = time.time()
            try:
                with open(path, "w") as f:
                    f.write(guard.text.replace(m["old"], m["new"], 1))
                state, failed, names = build_and_test(m["tests"], m["id"],
                                                      m["path"].startswith("tools/"))
            finally:
                guard.put_back()
            verdict = {"FAILED": "KILLED", "PASSED": "SURVIVED", "BUILD-ERROR": "BUILD-ERROR"}[state]
            results.append((m, verdict, failed))
            print(f"[audit] {k + 1}/{len(chosen)} {m['id']}: {verdict}"
                  f"{' by ' + ' '.join(failed) if failed else ''} ({time.time() - t0:.0f} s)", flush=True)
    except KeyboardInterrupt:
        print("[audit] interrupted; the mutated file was put back", flush=True)
    finally:
        # the build again as the sources are (the last mutation's objects are stale)
        if results or chosen:
            subprocess.run(["cmake", "--build", build, "-j", str(args.j)], cwd=ROOT, stdout=subprocess.DEVNULL,
                           stderr=subprocess.STDOUT)

    killed = sum(1 for _, v, _ in results if v == "KILLED")
    lines = [f"{m['id']:28s} {v:11s} {' '.join(f) if f else '-':40s} {m['path']}: {m['what']}"
             for m, v, f in results]
    summary = (f"killed {killed} of {len(results)} mutations"
               f" ({len(chosen) - len(results)} not run), {time.time() - t_all:.0f} s")
    with open(os.path.join(work, "results.txt"), "w") as f:
        f.write("\n".join(lines + [summary]) + "\n")
    print("\n".join(lines))
    print(f"[audit] {summary}; details in {work}")
    return 0 if killed == len(chosen) else 1


if __name__ == "__main__":
    sys.exit(main())
