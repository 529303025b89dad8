#!/usr/bin/env bash
# Runs the chain-network example end to end: data file, stage 1 (pretension), stage 2 (restart
# and stretch), report with pictures. Usage: run.sh [OUT] [STEPS]; needs build/ncf-env.sh.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
out=$(mkdir -p "${1:-$here/out}" && cd "${1:-$here/out}" && pwd)
steps=${2:-4000}
: "${NCF_BUILD:=$here/../../build}"
source "$NCF_BUILD/ncf-env.sh"
np=${NCF_NP:-1}
run_lmp() { if [ "$np" -gt 1 ]; then mpirun -np "$np" --oversubscribe lmp "$@"; else lmp "$@"; fi; }

cd "$out"
/usr/bin/python3 "$here/make_data.py" network.data

run_lmp -in "$here/in.pretension" -var out . -var steps "$steps" -log pretension.log -screen none
run_lmp -in "$here/in.stretch" -var out . -var steps "$steps" -log stretch.log -screen none
/usr/bin/python3 "$here/report.py" .
