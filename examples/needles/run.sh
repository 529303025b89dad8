#!/usr/bin/env bash
# Needle example: generate the small fabric, pierce it with the needle at its stitching point.
# Usage: run.sh [OUT]; needs tools/setup.sh to have run.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
out=$(mkdir -p "${1:-$here/out}" && cd "${1:-$here/out}" && pwd)
source "${NCF_BUILD:-$here/../../build}/ncf-env.sh"
cd "$here"
ncf-gen mini.card -o "$out/mini" -q
cd "$out"
lmp -in "$here/in.pierce" -var prefix mini -log pierce.log -screen none
grep '^PIERCE' pierce.log
