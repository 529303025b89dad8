#!/usr/bin/env bash
# ctest (label examples): the virtual tests on the small +-45 fabric (examples/manufacturing/
# small.card, about 1 600 nodes), released through the five manufacturing stages with short holds,
# then short versions of the compaction and the shear, through run.sh as a user runs them, and
# the checks of doc/howto_virtual_tests.md ("What is tested"):
#   kinematics   the box at the end of each shear segment is the prescribed one to round-off
#                (bias and square frames), the averaged PBC at round-off throughout
#   energy       the work of the box (from the virial) is not less than the energy stored
#   restart      a shear cut into pieces through its restart files (resume) gives the same curve
#   ranks        the shear on 2 MPI ranks gives the curve of 1 rank
#   friction     without friction (chains and plates) the mat compacts further at the same
#                pressure and the stitch loses its tension
#   stitch       on a square RVE of straight chains (square.card): with the yarn the sense that
#                stretches the stitch is by far the stiffer; without it the two senses differ
#                much less
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
mfg=$here/../manufacturing
out=${1:-$(mktemp -d)}
rm -rf "$out" && mkdir -p "$out"
short="-var hold 1000 -var release 1500 -var ramp 4000 -var relax 3000"
NCF_NP=1 NCF_LMP_ARGS="$short" NCF_ARGS_pierce="-var hold 2000" \
  bash "$mfg/run.sh" "$out" "$mfg/small.card" "$here/square.card" > "$out/manufacturing.out"
source "${NCF_BUILD:-$here/../../build}/ncf-env.sh"
cd "$out"
# the shear's arguments: 3 segments of 2 degrees, 300 steps per degree (the angle given with each
# run, first: LAMMPS keeps the first -var of a name)
sh_args="-var ramp 4000 -var dseg 2 -var degsteps 300"
# run.sh as a user runs it: both tests, both senses (a short compaction to 2 bar)
NCF_ANGLE=6 NCF_VT_ARGS="-var ramp 4000 -var dseg 2 -var degsteps 300" \
  NCF_ARGS_compaction="-var pmax 2e5 -var vdrag 0.05" bash "$here/run.sh" "$out" small > run.out
for f in small.compaction.dat small.shear-pos.dat small.shear-neg.dat virtual_tests.md \
  small.compaction_curve.png small.shear_curve.png small.shear-pos.png; do
  [ -s "$f" ] || { echo "FAIL: no $f"; exit 1; }
done
lmpv() { lmp -var prefix small -var here "$here" -screen none "$@"; }
# square frame (the box triclinic), cut into pieces through its restart files
# shellcheck disable=SC2086
lmpv -in "$here/in.shear" -var angle 6 $sh_args -var frame square -var out sq -log sq.log
# shellcheck disable=SC2086
lmpv -in "$here/in.shear" -var angle 6 $sh_args -var frame square -var out sqcut -var segments 1 \
  -log sqcut1.log
# shellcheck disable=SC2086
lmpv -in "$here/in.shear" -var angle 6 $sh_args -var frame square -var out sqcut -var resume 1 \
  -log sqcut2.log
# 2 ranks
# shellcheck disable=SC2086
mpirun -np 2 --oversubscribe lmp -var prefix small -var here "$here" -screen none -in "$here/in.shear" \
  -var angle 6 $sh_args -var frame bias -var out np2 -log np2.log
# the square RVE with and without the yarn, both senses
for y in keep delete; do
  for a in 6 -6; do
    # shellcheck disable=SC2086
    lmp -var prefix square -var here "$here" -screen none -in "$here/in.shear" -var angle $a $sh_args \
      -var frame bias -var yarn $y -var out square-$y$a -log square-$y$a.log
  done
done
# a frictionless compaction: chains and plates without friction
lmpv -in "$here/in.compaction" -var ramp 4000 -var pmax 2e5 -var vdrag 0.05 -var mu 0 -var mat_mu 0 \
  -var out mu0 -log mu0.log
/usr/bin/python3 -B "$here/check_virtual_tests.py" "$out"
