#!/usr/bin/env bash
# +-45 tricot NCF of the paper: generates the elementary RVE and the 3x3 RVE of the paper's
# comparison, and renders pictures with dump image.
#   bash run.sh [OUTDIR]        (default ./out; needs tools/setup.sh to have run)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
out=$(mkdir -p "${1:-$here/out}" && cd "${1:-$here/out}" && pwd)
source "${NCF_BUILD:-$here/../../build}/ncf-env.sh"
cd "$here"
ncf-gen ncf45.card -o "$out/ncf45" -q
ncf-gen ncf45.card -rve 3 3 -o "$out/ncf45-3x3" -q
cd "$out"
lmp -in "$here/render.lmp" -var prefix ncf45 -var out ncf45 -var zoom 1.5 -screen none -log none
echo "ncf45: summaries and pictures in $out"
