#!/usr/bin/env bash
# The main job: set-up (once), then the scenes that run end to end today, with pictures and a
# report in OUT/report.md:
#   1. the paper's two fabrics generated (ncf-gen): summaries and pictures of the layers and yarn
#   2. a periodic chain network: yarn pretension (stage 1, restart), stretch (stage 2), with the
#      box stress checked against the rod model
# Usage: bash tools/main.sh [OUT]      (default OUT: ./out)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
out=$(mkdir -p "${1:-$root/out}" && cd "${1:-$root/out}" && pwd)
export NCF_BUILD=${NCF_BUILD:-$root/build}
bash "$root/tools/setup.sh"

echo "[ncf-main] the paper's fabrics generated -> $out/fabrics"
bash "$root/examples/gen-ncf090/run.sh" "$out/fabrics" > /dev/null
bash "$root/examples/gen-ncf45/run.sh" "$out/fabrics" > /dev/null

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
  echo "## 2. Chain network: pretension and stretch"
  echo
  sed -n '3,$p' "$out/chain-network/report.md"
  echo
  echo "![stretch](chain-network/stress_strain.png)"
} > "$out/report.md"

echo
echo "[ncf-main] done. Report: $out/report.md"
echo "  fabrics  : $out/fabrics/*.summary, *.png (generated layers and yarn)"
echo "  network  : $out/chain-network/ (restarts, dumps, pictures, stress_strain.png)"
