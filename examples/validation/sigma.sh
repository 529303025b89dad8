#!/usr/bin/env bash
# The sigma study of the paper's Fig. 8: the 0/90 elementary RVE (examples/gen-ncf090/ncf090.card)
# with the orientation scatter sigma of both layers set to 0, 1, 2 and 3 deg, everything else as
# the card (Table 3), through the five manufacturing stages and ncf-measure; then a table of the
# channel width and the cracks against sigma (sigma.md) and the layers' deviation maps.
# Usage: bash examples/validation/sigma.sh OUT [sigma ...]     (default sigmas: 0 1 2 3)
#   NCF_NP (ranks, default 2), NCF_SEED, NCF_LMP_ARGS as for examples/manufacturing/run.sh.
# Needs build/ncf-env.sh sourced (lmp, ncf-gen, ncf-measure on PATH).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
out=$(mkdir -p "${1:?usage: sigma.sh OUT [sigma ...]}" && cd "$1" && pwd)
shift
sigmas=("$@")
[ ${#sigmas[@]} -gt 0 ] || sigmas=(0 1 2 3)
card="$root/examples/gen-ncf090/ncf090.card"
export NCF_NP=${NCF_NP:-2}
for s in "${sigmas[@]}"; do
  name="ncf090_s$s"
  # the card with both layers' sigma replaced, its name changed and the materials file absolute
  sed -e "s/^\(\s*sigma\s\+\)[0-9.eE+-]\+\s*deg/\1$s deg/" \
      -e "s/^name\s.*/name            $name/" \
      -e "s#^materials\s\+\S\+#materials       $root/potentials/ncf.materials#" "$card" > "$out/$name.card"
  n=$(grep -c "^\s*sigma\s\+$s deg" "$out/$name.card")
  [ "$n" = 2 ] || { echo "sigma.sh: expected two sigma lines in $card, found $n"; exit 1; }
  t0=$SECONDS
  bash "$root/examples/manufacturing/run.sh" "$out" "$out/$name.card"
  echo "$name wall_s $((SECONDS - t0)) ranks $NCF_NP" > "$out/$name.wall"
  ncf-measure "$out/$name.release.data" --needles "$out/$name.needles" --summary "$out/$name.summary" \
    --out "$out/measure-$name" -q
done
/usr/bin/python3 "$here/sigma_report.py" "$out" "${sigmas[@]}" > "$out/sigma.md"
echo "[sigma] table: $out/sigma.md"
