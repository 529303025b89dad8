#!/usr/bin/env bash
# The main job: set-up (once), then the scenes that run end to end today, with pictures and a
# report in OUT/report.md:
#   1. the paper's two fabrics generated (ncf-gen): summaries and pictures of the layers and yarn
#   2. stage 1 of the manufacturing for both fabrics (elementary RVE): compaction of the layers
#      to t_L between two plates under averaged periodic boundary conditions, pictures before and
#      after, compaction curve, checks (examples/manufacturing)
#   3. a periodic chain network: yarn pretension (stage 1, restart), stretch (stage 2), with the
#      box stress checked against the rod model
# Usage: bash tools/main.sh [OUT]      (default OUT: ./out)
# Environment: NCF_NP (MPI ranks of the compaction runs; default: 2 if the machine has 2 cores)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
out=$(mkdir -p "${1:-$root/out}" && cd "${1:-$root/out}" && pwd)
source "$root/tools/ncf-lammps.sh"    # NCF_LAMMPS=2026: against LAMMPS 4 Jul 2026
export NCF_BUILD=${NCF_BUILD:-$root/$ncf_default_build}
bash "$root/tools/setup.sh"

echo "[ncf-main] the paper's fabrics generated -> $out/fabrics"
bash "$root/examples/gen-ncf090/run.sh" "$out/fabrics" > /dev/null
bash "$root/examples/gen-ncf45/run.sh" "$out/fabrics" > /dev/null

np=${NCF_NP:-$(( $(nproc) >= 2 ? 2 : 1 ))}
echo "[ncf-main] stage 1, compaction of both fabrics on $np rank(s) (a few minutes) -> $out/manufacturing"
NCF_NP=$np bash "$root/examples/manufacturing/run.sh" "$out/manufacturing" ncf45 ncf090 \
  > "$out/manufacturing.out" 2>&1 || { tail -30 "$out/manufacturing.out"; exit 1; }

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
  echo "## 2. Stage 1: compaction to the layer thickness t_L"
  echo
  echo "Both fabrics, elementary RVE, \`examples/manufacturing/run.sh\` ($np MPI rank(s))."
  echo
  sed -n '1,$p' "$out/manufacturing/compaction.md" | sed 's/^## /### /'
  echo
  for f in ncf45 ncf090; do
    g=$(ls "$out/manufacturing/$f".generated.*.png | head -1)
    c=$(ls "$out/manufacturing/$f".compacted.*.png | head -1)
    echo "$f as generated and compacted:"
    echo
    echo "![$f generated](manufacturing/$(basename "$g")) ![$f compacted](manufacturing/$(basename "$c"))"
    echo
  done
  echo "![compaction curve](manufacturing/compaction_curve.png)"
  echo
  echo "## 3. Chain network: pretension and stretch"
  echo
  sed -n '3,$p' "$out/chain-network/report.md"
  echo
  echo "![stretch](chain-network/stress_strain.png)"
} > "$out/report.md"

echo
echo "[ncf-main] done. Report: $out/report.md"
echo "  fabrics  : $out/fabrics/*.summary, *.png (generated layers and yarn)"
echo "  stage 1  : $out/manufacturing/ (restarts, data, pictures, compaction_curve.png, logs)"
echo "  network  : $out/chain-network/ (restarts, dumps, pictures, stress_strain.png)"
