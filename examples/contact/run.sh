#!/bin/bash
# runs the pair ncf/contact examples in full; logs: log.crossed, log.mat (kept in the repository)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "${NCF_BUILD:-$here/../../build}/ncf-env.sh"
cd "$here"
lmp -in in.crossed -log log.crossed -screen none
lmp -in in.mat -log log.mat -screen none
grep -A8 "^ *Step" log.crossed | tail -4
grep -A14 "^ *Step" log.mat | tail -4
