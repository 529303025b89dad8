#!/usr/bin/env bash
# The main job: set-up (once), then the scenes that run end to end today, with pictures and a
# report in OUT/report.md:
#   1. the paper's two fabrics generated (ncf-gen): summaries and pictures of the layers and yarn
#   2. the manufacturing of both fabrics (elementary RVE), stages 1-5 (examples/manufacturing):
#      compaction to t_L, needle piercing, stitching, yarn pretension, release; pictures, the
#      checks of every stage, the as-manufactured fabric
#   3. a periodic chain network: yarn pretension (stage 1, restart), stretch (stage 2), with the
#      box stress checked against the rod model
#   then the released fabrics exported with their permeability, and their virtual tests, short
#   versions (examples/virtual-tests): compaction to 5 bar and back, shear to 20 deg both senses
# Usage: bash tools/main.sh [OUT]      (default OUT: ./out)
# Environment: NCF_NP (MPI ranks of the compaction runs; default: 2 if the machine has 2 cores)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
out=$(mkdir -p "${1:-$root/out}" && cd "${1:-$root/out}" && pwd)
source "$root/tools/ncf-lammps.sh"    # NCF_LAMMPS=2026: against LAMMPS 4 Jul 2026
export NCF_BUILD=${NCF_BUILD:-$root/$ncf_default_build}
bash "$root/tools/setup.sh"
source "$NCF_BUILD/ncf-env.sh"

echo "[ncf-main] the paper's fabrics generated -> $out/fabrics"
bash "$root/examples/gen-ncf090/run.sh" "$out/fabrics" > /dev/null
bash "$root/examples/gen-ncf45/run.sh" "$out/fabrics" > /dev/null

np=${NCF_NP:-$(( $(nproc) >= 2 ? 2 : 1 ))}
echo "[ncf-main] manufacturing stages 1-5 of both fabrics on $np rank(s) (several minutes) -> $out/manufacturing"
NCF_NP=$np bash "$root/examples/manufacturing/run.sh" "$out/manufacturing" ncf45 ncf090
(cd "$out/manufacturing" &&
  /usr/bin/python3 "$root/examples/manufacturing/report_compaction.py" ncf45.compact.log ncf090.compact.log --out . > /dev/null &&
  /usr/bin/python3 "$root/examples/manufacturing/report_manufacturing.py" ncf45 ncf090 --out manufacturing.md > /dev/null) ||
  echo "[ncf-main] WARNING: a check of the manufacturing failed, see $out/manufacturing/manufacturing.md"

echo "[ncf-main] measuring the as-manufactured fabrics (ncf-measure) -> $out/measure"
for f in ncf45 ncf090; do
  m="$out/manufacturing/$f"
  ncf-measure "$m.release.data" --needles "$m.needles" --summary "$m.summary" --out "$out/measure/$f" -q ||
    echo "[ncf-main] WARNING: ncf-measure failed on $f"
done

echo "[ncf-main] chain-network example (pretension, restart, stretch) -> $out/chain-network"
bash "$root/examples/chain-network/run.sh" "$out/chain-network" > /dev/null

# one report for everything
{
  echo "# USER-NCF main job report"
  echo
  echo "Generated $(date -u '+%Y-%m-%d %H:%M UTC'), USER-NCF $(git -C "$root" describe --always --dirty 2>/dev/null || echo unknown)."
  echo
  echo "## 1. The paper's fabrics as generated (ncf-gen)"
  echo
  for f in ncf090 ncf45; do
    echo "### $f"
    echo
    echo '```'
    sed -n '/^RVE/,/^checks/p' "$out/fabrics/$f.summary" | grep -E "size|courses|sum of t_L|stack top|nominal angle|chains, nodes|chains per mm|t_L =|sample std|diameter|critical time step \(all"
    echo '```'
    echo
    for p in "$out/fabrics/$f".oblique.*.png; do echo "![$f]($(basename "$(dirname "$p")")/$(basename "$p"))"; done
    echo
  done
  echo "## 2. Manufacturing, stages 1-5 (elementary RVEs)"
  echo
  echo "Both fabrics, \`examples/manufacturing/run.sh\` ($np MPI rank(s)); doc/howto_manufacturing.md"
  echo "explains every stage and check."
  echo
  sed 's/^## /### /' "$out/manufacturing/manufacturing.md" | sed 's#](\([a-z0-9_]*\.pressure\.png\))#](manufacturing/\1)#'
  echo
  for f in ncf45 ncf090; do
    echo "$f through the stages (generated, compacted, pierced, stitched, pretensioned, released):"
    echo
    g=$(ls "$out/manufacturing/$f".generated.*.png | head -1)
    printf '![%s generated](manufacturing/%s)' "$f" "$(basename "$g")"
    for st in compact pierce stitch pretension release; do
      printf ' ![%s %s](manufacturing/%s.%s.png)' "$f" "$st" "$f" "$st"
    done
    echo; echo
  done
  echo "### Stage 1 in detail: compaction to the layer thickness t_L"
  echo
  sed 's/^## /#### /' "$out/manufacturing/compaction.md"
  echo
  echo "![compaction curve](manufacturing/compaction_curve.png)"
  echo
  echo "## 3. The as-manufactured fabrics, measured as the paper's scans (ncf-measure)"
  echo
  echo "Each layer seen from its free face with the other layer and the yarn removed, coloured by the"
  echo "local deviation from its nominal angle, the gaps outlined and sized (doc/ncf_measure.md)."
  echo "The elementary RVEs have only 2 (±45°) and 4 (0°/90°) stitching points: few measurements;"
  echo "the paper's comparison uses larger RVEs and three seeds (§5.2)."
  echo
  /usr/bin/python3 "$root/examples/manufacturing/compare_paper.py" \
    --ncf090 "$out/measure/ncf090/ncf-measure-summary.csv" --ncf45 "$out/measure/ncf45/ncf-measure-summary.csv" || true
  echo
  for f in ncf45 ncf090; do
    echo "$f as manufactured (oblique, with the yarn) and each layer from its free face:"
    echo
    printf '![%s released](manufacturing/%s.release.png)' "$f" "$f"
    for mp in "$out/measure/$f/"*-map.png; do
      [ -f "$mp" ] && printf ' ![%s](measure/%s/%s)' "$(basename "$mp" .png)" "$f" "$(basename "$mp")"
    done
    echo; echo
    sed -n '/^## Orientation/,$p' "$out/measure/$f/ncf-measure.md" | sed 's/^## /#### /'
    echo
    echo "![orientation](measure/$f/ncf-measure-orientation.png)"
    echo
  done
  echo "## 4. Chain network: pretension and stretch"
  echo
  sed -n '3,$p' "$out/chain-network/report.md"
  echo
  echo "![stretch](chain-network/stress_strain.png)"
} > "$out/report.md"
echo "[ncf-main] exports (VTU, VTI) and permeability of the released fabrics (ncf-export, ncf-perm) -> $out/manufacturing"
{ echo; echo "## 5. The released fabrics exported, and their permeability"; echo; for f in ncf45 ncf090; do bash "$root/examples/manufacturing/export_perm.sh" "$out/manufacturing/$f" || echo "WARNING: export or permeability of $f failed"; done; } >> "$out/report.md"

echo "[ncf-main] virtual tests of the released fabrics, short versions (compaction, shear both senses) -> $out/manufacturing"
# (short: the plate at 5 % damping drag, 20 deg at 300 steps per degree; doc/howto_virtual_tests.md
# gives the full test and what the speeds change)
if NCF_NP=$np NCF_ANGLE=20 NCF_ARGS_compaction="-var vdrag 0.05" NCF_ARGS_shear="-var dseg 2 -var degsteps 300" \
  bash "$root/examples/virtual-tests/run.sh" "$out/manufacturing" ncf45 ncf090 > "$out/manufacturing/virtual_tests.out"; then
  { echo; echo "## 6. Virtual tests of the released fabrics (short versions)"; echo
    sed -n '3,$p' "$out/manufacturing/virtual_tests.md" | sed 's/^## /### /; s/^### Compaction/#### Compaction/; s/^### In-plane/#### In-plane/' |
      sed 's#](\([A-Za-z0-9_.-]*\.png\))#](manufacturing/\1)#'; } >> "$out/report.md"
else
  echo "[ncf-main] WARNING: a virtual test failed, see $out/manufacturing/virtual_tests.out"
  { echo; echo "## 6. Virtual tests: FAILED (see manufacturing/virtual_tests.out)"; } >> "$out/report.md"
fi

echo
echo "[ncf-main] done. Report: $out/report.md"
echo "  fabrics  : $out/fabrics/*.summary, *.png (generated layers and yarn)"
echo "  stages   : $out/manufacturing/ (per fabric and stage: restart, data, dump, png, log; manufacturing.md)"
echo "  measured : $out/measure/<fabric>/ (layer maps, orientation, ncf-measure.md, CSV)"
echo "  network  : $out/chain-network/ (restarts, dumps, pictures, stress_strain.png)"
echo "  vtests   : $out/manufacturing/virtual_tests.md, <fabric>.compaction_curve.png, <fabric>.shear_curve.png"
