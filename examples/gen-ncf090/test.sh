#!/usr/bin/env bash
# Brief check of this example (ctest label examples): tools/check_gen_example.sh.
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
exec bash "$here/../../tools/check_gen_example.sh" "$here" "${1:?usage: test.sh OUTDIR}" \
  "ncf090 ncf090-2x2" "ncf090.oblique.0.png ncf090.top1.0.png ncf090-periodic.yarn.0.png"
