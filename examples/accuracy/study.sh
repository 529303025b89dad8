#!/usr/bin/env bash
# The accuracy study (doc/accuracy_cost.md): one fabric through the five manufacturing stages and
# the measurement, varying one parameter at a time around the paper's values (variants.txt), each
# with several seeds; per run the metrics of ncf-measure, the fabric thickness after release, the
# largest penetration, the steps, the wall time and the peak memory; then study_report.py writes
# OUT/accuracy.md and OUT/accuracy.csv (the error of each run against the reference variant).
#
# Usage: bash examples/accuracy/study.sh OUT [SEED ...]                (default seeds: 1 2 3)
#   NCF_STUDY_CARD   fabric: ncf45 (default), ncf090, or the path of a card
#   NCF_STUDY        the variants to run, e.g. "base d98 m04" (default: all of variants.txt)
#   NCF_STUDY_REF    the reference variant (default: fine)
#   NCF_NP           MPI ranks (default 1: the wall times of the doc are 1-rank times)
# A run already complete in OUT (its measurement exists) is not repeated. About 1.5 to 15 minutes per
# run of the +-45 elementary RVE on one idle core (the reference the longest).
set -eEuo pipefail
trap 'echo "[accuracy] stopped by a failing command (status $?), line $LINENO: $BASH_COMMAND"' ERR
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
out=$(mkdir -p "${1:?usage: study.sh OUT [SEED ...]}" && cd "$1" && pwd)
shift
seeds=("$@")
[ ${#seeds[@]} -gt 0 ] || seeds=(1 2 3)
: "${NCF_BUILD:=$root/build}"
export NCF_BUILD
source "$NCF_BUILD/ncf-env.sh"
export NCF_NP=${NCF_NP:-1}
fabric=${NCF_STUDY_CARD:-ncf45}
if [[ "$fabric" == *.card ]]; then
  card=$(cd "$(dirname "$fabric")" && pwd)/$(basename "$fabric")
else
  card="$root/examples/gen-$fabric/$fabric.card"
fi
[ -f "$card" ] || { echo "study.sh: no fabric card '$fabric' ($card)"; exit 1; }

# the variants: name | card lines | LAMMPS arguments | NCF_PDYN | description
declare -A vcard vargs vpdyn
names=()
trim() { local s=$1; s=${s#"${s%%[![:space:]]*}"}; echo "${s%"${s##*[![:space:]]}"}"; }
while IFS='|' read -r name lines args pdyn _; do
  [[ "$name" =~ ^[[:space:]]*(#|$) ]] && continue
  name=$(trim "$name")
  names+=("$name")
  vcard[$name]=$(trim "$lines")
  vargs[$name]=$(trim "$args")
  vpdyn[$name]=$(trim "$pdyn")
done < "$here/variants.txt"
run_names=(${NCF_STUDY:-${names[@]}})
for v in "${run_names[@]}"; do
  [ -n "${vcard[$v]+x}" ] || { echo "study.sh: unknown variant '$v' (variants.txt: ${names[*]})"; exit 1; }
done

# the card of a variant: the fabric card with the variant's lines in place of the lines of the
# same keywords (each keyword must be in the card once, so that nothing is silently added or left)
# and its lines written '+keyword value' added (the keyword must not be in the card) and those
# written '-keyword' removed (the keyword must be in the card once), the materials file made absolute
key_count() { awk -v k="$1" '$1 == k' "$2" | wc -l; }    # keyword file: its lines in the file
make_card() {    # variant file
  local v=$1 dst=$2 mat
  mat=$(awk '$1 == "materials" { print $2; exit }' "$card")
  [[ "$mat" == /* ]] || mat="$(dirname "$card")/$mat"
  awk -v mat="$mat" '$1 == "materials" { print "materials " mat; next } { print }' "$card" > "$dst"
  [ "${vcard[$v]}" = "-" ] && return 0
  local line key n
  IFS=';' read -ra lines <<< "${vcard[$v]}"
  for line in "${lines[@]}"; do
    line=$(trim "$line")
    if [[ "$line" == -* ]]; then
      key=${line#-}
      n=$(key_count "$key" "$dst")
      [ "$n" = 1 ] || { echo "study.sh: variant $v: keyword '$key' to remove is in the card $n times (needs 1)"; exit 1; }
      awk -v k="$key" '$1 != k' "$dst" > "$dst.tmp"
      mv "$dst.tmp" "$dst"
      continue
    fi
    if [[ "$line" == +* ]]; then
      line=${line#+}
      key=${line%% *}
      n=$(key_count "$key" "$dst")
      [ "$n" = 0 ] || { echo "study.sh: variant $v: keyword '$key' to add is in the card already"; exit 1; }
      printf '%s    # study variant\n' "$line" >> "$dst"
      continue
    fi
    key=${line%% *}
    n=$(key_count "$key" "$dst")
    [ "$n" = 1 ] || { echo "study.sh: variant $v: keyword '$key' is in the card $n times (needs 1)"; exit 1; }
    awk -v k="$key" -v l="$line" '$1 == k { print l "    # study variant"; next } { print }' "$dst" > "$dst.tmp"
    mv "$dst.tmp" "$dst"
  done
}

for v in "${run_names[@]}"; do
  for seed in "${seeds[@]}"; do
    dir="$out/$v-seed$seed"
    if [ -s "$dir/measure/ncf-measure-summary.csv" ]; then
      echo "[accuracy] $v seed $seed: done before ($dir)"
      continue
    fi
    rm -rf "$dir" && mkdir -p "$dir"
    make_card "$v" "$dir/study.card"
    prefix=$(awk '$1 == "name" { print $2; exit }' "$dir/study.card")
    # the LAMMPS arguments: for every stage, or 'stage: arguments' for one stage (';' between)
    args="" stage_env=()
    if [ "${vargs[$v]}" != "-" ]; then
      IFS=';' read -ra parts <<< "${vargs[$v]}"
      for part in "${parts[@]}"; do
        part=$(trim "$part")
        if [[ "$part" =~ ^(compact|pierce|stitch|pretension|release):(.*)$ ]]; then
          stage_env+=("NCF_ARGS_${BASH_REMATCH[1]}=$(trim "${BASH_REMATCH[2]}")")
        elif [[ "$part" =~ ^[a-z]+: ]]; then
          echo "study.sh: variant $v: '${part%%:*}' is not a stage (compact pierce stitch pretension release)"; exit 1
        else
          args="$args $part"
        fi
      done
    fi
    pdyn=${vpdyn[$v]}
    [ "$pdyn" = "-" ] && pdyn=""    # the card's quality preset (ncf_pdyn of the settings)
    echo "[accuracy] $v seed $seed: $(date -u '+%H:%M:%S')"
    # GNU time: the wall time and the largest resident memory of any process of the run
    /usr/bin/time -f "%e %M" -o "$dir/time" env NCF_SEED="$seed" NCF_PDYN="$pdyn" NCF_LMP_ARGS="$args" "${stage_env[@]}" \
      bash "$root/examples/manufacturing/run.sh" "$dir" "$dir/study.card" > "$dir/run.out" 2>&1 ||
      { echo "[accuracy] $v seed $seed FAILED: $dir/run.out"; tail -5 "$dir/run.out"; continue; }
    echo "$v $seed $NCF_NP $(cat "$dir/time") $prefix" > "$dir/run.info"
    ncf-measure "$dir/$prefix.release.data" --needles "$dir/$prefix.needles" \
      --summary "$dir/$prefix.summary" --out "$dir/measure" -q
  done
done
/usr/bin/python3 -B "$here/study_report.py" "$out" --ref "${NCF_STUDY_REF:-fine}" \
  --variants "$here/variants.txt"
echo "[accuracy] report: $out/accuracy.md"
