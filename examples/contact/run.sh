#!/bin/bash
# runs the pair ncf/contact examples in full; logs named as LAMMPS's examples name theirs,
# log.<DDMonYY>.crossed.g++.1 and log.<DDMonYY>.mat.g++.1 (kept in the repository)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "${NCF_BUILD:-$here/../../build}/ncf-env.sh"
cd "$here"
day=$(LC_ALL=C date +%d%b%y)
lmp -in in.crossed -log log.$day.crossed.g++.1 -screen none
lmp -in in.mat -log log.$day.mat.g++.1 -screen none
grep -A8 "^ *Step" log.$day.crossed.g++.1 | tail -4
grep -A14 "^ *Step" log.$day.mat.g++.1 | tail -4
