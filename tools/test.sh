#!/usr/bin/env bash
# The test command: set-up (once), build, then every test suite through ctest:
#   unit (engine-free kernels), integration (LAMMPS + plugin), mpi (1/2/4 ranks), examples.
# Usage: bash tools/test.sh [extra ctest arguments, e.g. -L unit]
# NCF_LAMMPS=2026 tests against LAMMPS 4 Jul 2026 in ./build-lammps2026 (default 2025: LAMMPS
# 4 Feb 2025 in ./build); NCF_BUILD moves the folder (tools/ncf-lammps.sh).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
source "$root/tools/ncf-lammps.sh"
export NCF_BUILD=${NCF_BUILD:-$root/$ncf_default_build}
bash "$root/tools/setup.sh"
cd "$NCF_BUILD"
ctest --output-on-failure -j 2 "$@"
