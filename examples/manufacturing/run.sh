#!/usr/bin/env bash
# The paper's manufacturing stages for a fabric card (stage 1 so far: compaction of the layers
# between two plates under averaged periodic boundary conditions), with pictures and a report.
#
# Usage: run.sh [OUT] [FABRIC ...]       FABRIC: ncf090 (0/90 tricot-chain), ncf45 (+-45 tricot)
# Environment: NCF_NP (MPI ranks, default 1), NCF_PDYN (accepted dynamic pressure, Pa),
#              NCF_SEED (random seed of the chain angles), NCF_RVE ("R_W R_L", default "1 1").
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
out=$(mkdir -p "${1:-$here/out}" && cd "${1:-$here/out}" && pwd)
shift || true
fabrics=("$@")
[ ${#fabrics[@]} -gt 0 ] || fabrics=(ncf45 ncf090)
: "${NCF_BUILD:=$here/../../build}"
source "$NCF_BUILD/ncf-env.sh"
np=${NCF_NP:-1}
pdyn=${NCF_PDYN:-1e4}
run_lmp() { if [ "$np" -gt 1 ]; then mpirun -np "$np" --oversubscribe lmp "$@"; else lmp "$@"; fi; }

cd "$out"
logs=()
for fab in "${fabrics[@]}"; do
  card="$here/../gen-$fab/$fab.card"
  [ -f "$card" ] || { echo "run.sh: no card for fabric '$fab' ($card)"; exit 1; }
  args=(-o "$fab" -q)
  [ -n "${NCF_SEED:-}" ] && args+=(-seed "$NCF_SEED")
  [ -n "${NCF_RVE:-}" ] && args+=(-rve ${NCF_RVE})
  ncf-gen "$card" "${args[@]}"
  echo "[manufacturing] $fab: stage 1, compaction ($(grep 'total atoms' $fab.summary | awk '{print $5}') nodes, $np rank(s))"
  run_lmp -in "$here/in.compact" -var prefix "$fab" -var pdyn "$pdyn" -log "$fab.compact.log" -screen none
  logs+=("$fab.compact.log")
done
/usr/bin/python3 "$here/report_compaction.py" "${logs[@]}" --out .
