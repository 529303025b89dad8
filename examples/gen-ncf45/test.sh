#!/usr/bin/env bash
# Brief check of this example (ctest label examples): run.sh into OUTDIR, then compare the robust
# lines of the summaries (counts, sizes, t_L) with the reference summaries kept here.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
out=${1:?usage: test.sh OUTDIR}
rm -rf "$out"
bash "$here/run.sh" "$out"
keys='size Lx|courses, needles|t_L = A|chains, nodes, bonds|chains per mm|yarns, nodes|chain diameter'
status=0
for s in ncf45 ncf45-3x3; do
  if ! diff <(grep -E "$keys" "$here/$s.summary") <(grep -E "$keys" "$out/$s.summary"); then
    echo "FAIL: $s.summary differs from the reference"
    status=1
  fi
done
for png in ncf45.oblique.0.png ncf45.top1.0.png; do
  [ -s "$out/$png" ] || { echo "FAIL: no $png"; status=1; }
done
exit $status
