#!/usr/bin/env bash
# 0/90 tricot-chain NCF of the paper: generates the elementary RVE, the 2x2 RVE of the paper's
# comparison and the purely periodic (sigma = 0) variant, and renders pictures with dump image.
#   bash run.sh [OUTDIR]        (default ./out; needs tools/setup.sh to have run)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
out=$(mkdir -p "${1:-$here/out}" && cd "${1:-$here/out}" && pwd)
source "${NCF_BUILD:-$here/../../build}/ncf-env.sh"
cd "$here"
ncf-gen ncf090.card -o "$out/ncf090" -q
ncf-gen ncf090.card -rve 2 2 -o "$out/ncf090-2x2" -q
ncf-gen ncf090-periodic.card -o "$out/ncf090-periodic" -q
cd "$out"
lmp -in "$here/render.lmp" -var prefix ncf090 -var out ncf090 -screen none -log none
lmp -in "$here/render.lmp" -var prefix ncf090-periodic -var out ncf090-periodic -var yarn 1 \
  -screen none -log none
echo "ncf090: summaries and pictures in $out"
