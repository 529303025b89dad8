#!/usr/bin/env bash
# The as-manufactured fabric for other tools: ParaView/meshio exports and the permeability tensor.
#   bash export_perm.sh DIR/FABRIC [STAGE] [VOXEL] >> report.md
# reads DIR/FABRIC.STAGE.data (default stage: release) and DIR/FABRIC.summary, writes
# DIR/FABRIC.STAGE.vtu (chains as line cells), .vti and .vtk (voxel grid, VOXEL default 80um) and
# DIR/FABRIC.STAGE.perm.log (ncf-perm's output), and prints a markdown fragment with the tensor.
# Needs ncf-export and ncf-perm on the PATH (source build/ncf-env.sh). doc/ncf_export.md,
# doc/ncf_perm.md. Environment: NCF_PERM_TOL (default 1e-4), NCF_PERM_THREADS (default: cores).
set -euo pipefail
prefix=${1:?usage: export_perm.sh DIR/FABRIC [STAGE] [VOXEL]}
stage=${2:-release}
voxel=${3:-80um}
data="$prefix.$stage.data"
name=$(basename "$prefix")
for f in "$data" "$prefix.summary"; do
  [ -f "$f" ] || { echo "export_perm.sh: $f does not exist" >&2; exit 1; }
done
out="$prefix.$stage"
ncf-export "$data" --summary "$prefix.summary" --vtu "$out.vtu" --vti "$out.vti" --vtk "$out.vtk" \
  --voxel "$voxel" > "$out.export.log"
threads=${NCF_PERM_THREADS:-$(nproc)}
start=$(date +%s)
ncf-perm "$out.vti" --tol "${NCF_PERM_TOL:-1e-4}" --threads "$threads" > "$out.perm.log" || {
  echo "export_perm.sh: ncf-perm failed on $out.vti (see $out.perm.log)" >&2; exit 1; }
secs=$(( $(date +%s) - start ))
echo "### $name, stage $stage: exports and permeability"
echo
echo "Exports: \`$name.$stage.vtu\` (chains and yarn as line cells; ParaView: Tube filter by \`radius\`),"
echo "\`$name.$stage.vti\` / \`.vtk\` (voxel grid: \`vf\`, \`dir\`, \`a2\`, \`phase\`; doc/ncf_export.md)."
echo
echo '```'
sed -n 's/^ncf-export: //p' "$out.export.log"
grep -E "^ncf-perm: (cells|iterations|largest|symmetry)" "$out.perm.log" | sed 's/^ncf-perm: //'
echo '```'
echo
echo "Permeability tensor K [m²] (x machine direction, y gauge direction, z thickness; the grid"
echo "periodic in z: plies stacked without nesting; voxel $voxel, Brinkman–Gebart in the chains;"
echo "ncf-perm, $secs s; doc/ncf_perm.md):"
echo
echo "| | x | y | z |"
echo "|---|---|---|---|"
tail -3 "$out.perm.log" | awk '{ printf "| %s | %s | %s | %s |\n", substr("xyz", NR, 1), $1, $2, $3 }'
echo
