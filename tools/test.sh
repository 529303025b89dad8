#!/usr/bin/env bash
# The test command: set-up (once), build, then every test suite through ctest:
#   unit (engine-free kernels), integration (LAMMPS + plugin), mpi (1/2/4 ranks), examples.
# Usage: bash tools/test.sh [extra ctest arguments, e.g. -L unit]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
export NCF_BUILD=${NCF_BUILD:-$root/build}
bash "$root/tools/setup.sh"
cd "$NCF_BUILD"
ctest --output-on-failure -j 2 "$@"
