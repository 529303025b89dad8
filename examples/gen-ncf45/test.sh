#!/usr/bin/env bash
# Brief check of this example (ctest label examples): tools/check_gen_example.sh.
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
exec bash "$here/../../tools/check_gen_example.sh" "$here" "${1:?usage: test.sh OUTDIR}" \
  "ncf45 ncf45-3x3" "ncf45.oblique.0.png ncf45.top1.0.png"
