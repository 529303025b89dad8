#!/usr/bin/env bash
# The main job: set-up (once), then the default example end to end with its pictures and report.
# Usage: bash tools/main.sh [OUT]      (default OUT: ./out)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
out=${1:-$root/out}
export NCF_BUILD=${NCF_BUILD:-$root/build}
bash "$root/tools/setup.sh"

echo "[ncf-main] chain-network example (pretension, restart, stretch) -> $out/chain-network"
bash "$root/examples/chain-network/run.sh" "$out/chain-network"

echo
echo "[ncf-main] done. Outputs:"
echo "  report   : $out/chain-network/report.md"
echo "  pictures : $out/chain-network/stretch.*.png, $out/chain-network/stress_strain.png"
echo "  restarts : $out/chain-network/pretension.restart, stretch.restart; data: final.data"
echo "  logs     : $out/chain-network/*.log"
