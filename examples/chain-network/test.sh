#!/usr/bin/env bash
# ctest (label examples): the chain-network example, briefly, on 2 ranks; the report checks the
# stresses against the analytic values and the expected files must exist.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
out=${1:-$(mktemp -d)}
rm -rf "$out" && mkdir -p "$out"
NCF_NP=2 bash "$here/run.sh" "$out" 1500
for f in pretension.restart stretch.restart final.data report.md stress_strain.png; do
  [ -s "$out/$f" ] || { echo "missing output $f"; exit 1; }
done
ls "$out"/stretch.*.png >/dev/null
ls "$out"/stretch.*.dump >/dev/null
grep -q "^NCF_CHAIN_L0" "$out/final.data" || { echo "final.data has no NCF_CHAIN_L0 section"; exit 1; }
echo "chain-network example: outputs and stresses OK"
