#!/usr/bin/env bash
# Shared check of the generator examples (examples/gen-*/test.sh): run the example's run.sh into
# OUTDIR, compare the robust lines of the summaries (counts, sizes, t_L) with the reference
# summaries kept in the example folder, and require the pictures.
# Usage: check_gen_example.sh EXAMPLE_DIR OUTDIR "SUMMARY ..." "PICTURE ..."
set -euo pipefail
here=$1 out=$2 summaries=$3 pictures=$4
rm -rf "$out"
bash "$here/run.sh" "$out"
keys='size Lx|courses, needles|t_L = A|chains, nodes, bonds|chains per mm|yarns, nodes|chain diameter'
status=0
for s in $summaries; do
  if ! diff <(grep -E "$keys" "$here/$s.summary") <(grep -E "$keys" "$out/$s.summary"); then
    echo "FAIL: $s.summary differs from the reference"
    status=1
  fi
done
for png in $pictures; do
  [ -s "$out/$png" ] || { echo "FAIL: no $png"; status=1; }
done
exit $status
