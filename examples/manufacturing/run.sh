#!/usr/bin/env bash
# The paper's manufacturing sequence for one or more fabric cards, stages 1-5 (paper section 4.4,
# doc/howto_manufacturing.md), with each stage's pictures and its run-time checks (no pass-through,
# the needle guards); the checks of the fabric and the report are report_manufacturing.py's (run.sh
# prints the command at the end; tools/main.sh runs both):
#   1 compact     the generated layers squeezed to sum(t_L) between two plates (in.compact)
#   2 pierce      the in-plane hold of the chain ends let go, needles through the mat (in.pierce)
#   3 stitch      the stitching yarn added through the needle holes, needles out (in.stitch)
#   4 pretension  the yarn's rest length shrinks by the card's pretension (in.pretension)
#   5 release     the plates removed, the fabric relaxes: the "as-manufactured" state (in.release)
# Each stage starts from the previous stage's restart file and writes PREFIX.STAGE.{restart,data,
# dump,png} and PREFIX.STAGE.log into OUT.
#
# Usage: run.sh [OUT] [FABRIC ...]
#   FABRIC: ncf090 (0/90 tricot-chain), ncf45 (+-45 tricot) - the cards under examples/gen-*/ -
#           or the path of any fabric card (doc/ncf-gen.md); default: ncf45 ncf090
# Environment:
#   NCF_NP       MPI ranks (default 1)
#   NCF_STAGES   stages to run, e.g. "1-5" (default), "1", "3-5" (the earlier ones' restart files
#                must be in OUT)
#   NCF_SEED     random seed of the chain angles (default: the card's)
#   NCF_RVE      "R_W R_L" RVE repetitions (default: the card's)
#   NCF_PDYN     accepted dynamic pressure of the compaction [Pa] (default: the card's quality
#                preset, doc/ncf-gen.md; 1e4 for quality standard)
#   NCF_LMP_ARGS extra LAMMPS arguments for every stage, e.g. "-var tau 1000"
#   NCF_ARGS_<stage>  extra LAMMPS arguments for one stage, e.g. NCF_ARGS_pierce="-var hold 500";
#                they come first, so they win over NCF_LMP_ARGS (LAMMPS keeps the first -var)
set -eEuo pipefail
trap 'echo "[manufacturing] run.sh: stopped by a failing command (status $?), line $LINENO: $BASH_COMMAND"' ERR
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
dest=${1:-$here/out}
shift || true
fabrics=("$@")
[ ${#fabrics[@]} -gt 0 ] || fabrics=(ncf45 ncf090)
# the inputs, checked before anything is made (the stage variables are checked by the stage
# scripts themselves, ncf/check; NCF_PDYN by in.compact's pdyn)
np=${NCF_NP:-1}
[[ "$np" =~ ^[1-9][0-9]{0,3}$ ]] ||
  { echo "run.sh: NCF_NP='$np' is not a number of MPI ranks (an integer 1..9999)"; exit 1; }
stages_all=(compact pierce stitch pretension release)
range=${NCF_STAGES:-1-5}
first=${range%-*} last=${range#*-}
[[ "$first" =~ ^[1-5]$ && "$last" =~ ^[1-5]$ && $first -le $last ]] ||
  { echo "run.sh: NCF_STAGES='$range' is not a stage range like 1-5 or 3"; exit 1; }
[ -z "${NCF_SEED:-}" ] || [[ "$NCF_SEED" =~ ^[0-9]{1,18}$ ]] ||
  { echo "run.sh: NCF_SEED='$NCF_SEED' is not a seed (an integer >= 0)"; exit 1; }
[ -z "${NCF_RVE:-}" ] || [[ "$NCF_RVE" =~ ^[1-9][0-9]{0,3}\ [1-9][0-9]{0,3}$ ]] ||
  { echo "run.sh: NCF_RVE='$NCF_RVE' is not 'R_W R_L' (two integers >= 1)"; exit 1; }
# the cards, relative to the folder run.sh is started from
cards=()
for fab in "${fabrics[@]}"; do
  if [[ "$fab" == *.card ]]; then
    [ -f "$fab" ] || { echo "run.sh: no fabric card '$fab'"; exit 1; }
    cards+=("$(cd "$(dirname "$fab")" && pwd)/$(basename "$fab")")
  else
    card="$here/../gen-$fab/$fab.card"
    [ -f "$card" ] ||
      { echo "run.sh: no fabric card '$fab' ($card; give ncf45, ncf090 or the path of a card)"; exit 1; }
    cards+=("$card")
  fi
done
if [ -e "$dest" ] && [ ! -d "$dest" ]; then
  echo "run.sh: OUT '$dest' exists and is not a folder"
  exit 1
fi
out=$(mkdir -p "$dest" && cd "$dest" && pwd)
: "${NCF_BUILD:=$here/../../build}"
source "$NCF_BUILD/ncf-env.sh"
# the compaction's dynamic pressure only when asked for: else the card's quality preset sets it
pdyn_arg=()
[ -n "${NCF_PDYN:-}" ] && pdyn_arg=(-var pdyn "$NCF_PDYN")

run_lmp() { if [ "$np" -gt 1 ]; then mpirun -np "$np" --oversubscribe lmp "$@"; else lmp "$@"; fi; }

# progress of a running stage from its log: the stage prints "STAGE_PLAN first F steps N"
# before its runs, thermo lines carry the step
progress() {
  # (the log appears only once LAMMPS has started: several seconds with many ranks on a busy machine)
  [ -r "$1" ] || { printf 'starting, %d s elapsed' "$2"; return 0; }
  awk -v t="$2" '
    $1 == "STAGE_PLAN" { f = $3; n = $5 }
    $1 ~ /^[0-9]+$/ && NF > 4 { s = $1 }
    END { if (n > 0 && s != "") { d = s - f; if (d < 0) d = 0; if (d > n) d = n
            left = (d > 0) ? t * (n - d) / d : -1
            printf "step %d of %d (%d %%), %d s elapsed", d, n, 100 * d / n, t
            if (left >= 0) printf ", about %d s left", left }
          else printf "starting, %d s elapsed", t }' "$1" 2>/dev/null
}

run_stage() {    # fab index name
  local fab=$1 k=$2 name=$3 log="$1.$3.log" t0=$SECONDS pid line tty=0
  [ -t 1 ] && tty=1
  local extra="NCF_ARGS_$name"
  # shellcheck disable=SC2086  (word splitting of the extra arguments is wanted)
  run_lmp -in "$here/in.$name" -var prefix "$fab" -var here "$here" "${pdyn_arg[@]}" \
    ${!extra:-} ${NCF_LMP_ARGS:-} -log "$log" -screen none &
  pid=$!
  local last_print=$SECONDS
  while kill -0 $pid 2>/dev/null; do
    sleep 2
    line=$(progress "$log" $((SECONDS - t0)))
    if [ $tty = 1 ]; then
      printf '\r\033[K[manufacturing] %s stage %d/5 %-10s %s' "$fab" "$k" "$name" "$line"
    elif ((SECONDS - last_print >= 30)); then
      echo "[manufacturing] $fab stage $k/5 $name: $line"
      last_print=$SECONDS
    fi
  done
  if ! wait $pid; then
    [ $tty = 1 ] && echo
    echo "[manufacturing] $fab stage $k/5 $name FAILED after $((SECONDS - t0)) s; the end of $out/$log:"
    tail -15 "$log"
    return 1
  fi
  [ $tty = 1 ] && printf '\r\033[K'
  echo "[manufacturing] $fab stage $k/5 $name done in $((SECONDS - t0)) s ($(progress "$log" 0 | sed 's/,.*//'))"
}

# (the card paths were resolved relative to where run.sh was called from, above: cards)
cd "$out"
for card in "${cards[@]}"; do
  # the output prefix: the card's name
  name=$(awk '$1 == "name" { print $2; exit }' "$card")
  name=${name:-$(basename "$card" .card)}
  if [ "$first" = 1 ]; then
    args=(-o "$name" -q)
    [ -n "${NCF_SEED:-}" ] && args+=(-seed "$NCF_SEED")
    # shellcheck disable=SC2206
    [ -n "${NCF_RVE:-}" ] && args+=(-rve ${NCF_RVE})
    ncf-gen "$card" "${args[@]}"
  fi
  echo "[manufacturing] $name: $(grep 'total atoms' "$name.summary" | awk '{print $4}' | tr -d ,) nodes with the yarn, $np rank(s), stages $first-$last"
  for k in $(seq "$first" "$last"); do
    run_stage "$name" "$k" "${stages_all[k - 1]}"
  done
  if [ "$last" = 5 ]; then
    echo "[manufacturing] $name: the checks and the report:" \
      "python3 $here/report_manufacturing.py $name --dir $out --out $out/$name.report.md"
  fi
done
