#!/usr/bin/env bash
# Recompute the tables of doc/validation.md and doc/accuracy_cost.md from the files kept in
# results/, without running LAMMPS, and compare them with the kept reports.
# Usage (from the repository root):
#   bash results/recompute.sh                    every table, compared with the kept reports
#   bash results/recompute.sh study accuracy base  one study's report (here against `base`) on stdout
# Needs python3; nothing in results/ is changed (the reports are written to a temporary folder).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
py=/usr/bin/python3
[ -x "$py" ] || py=python3
status=0

# The accuracy studies: study_report.py reads OUT/<variant>-seed<N>/<prefix>.<stage>.log; the
# kept <prefix>.<stage>.extract holds the only lines of the log it reads (the "Loop time" lines
# and the stage's summary line), so a copy with the extracts renamed is a study folder for it.
study() {  # study <folder under results/> <reference variant>
  local d="$tmp/$1"
  mkdir -p "$d" && cp -r "results/$1/." "$d/"
  find "$d" -name '*.extract' | while read -r f; do mv "$f" "${f%.extract}.log"; done
  "$py" -B examples/accuracy/study_report.py "$d" --ref "$2" > /dev/null
  for f in accuracy.md accuracy.csv; do
    if [ -f "results/$1/$f" ]; then
      if cmp -s "$d/$f" "results/$1/$f"; then echo "results/$1/$f: recomputed, the same"
      else echo "results/$1/$f: recomputed, DIFFERS:"; diff "results/$1/$f" "$d/$f" | head -20; status=1; fi
    fi
  done
}
if [ "${1:-}" = study ]; then
  [ $# -eq 3 ] || { echo "usage: recompute.sh study FOLDER REFERENCE" >&2; exit 2; }
  d="$tmp/$2"
  mkdir -p "$d" && cp -r "results/$2/." "$d/"
  find "$d" -name '*.extract' | while read -r f; do mv "$f" "${f%.extract}.log"; done
  "$py" -B examples/accuracy/study_report.py "$d" --ref "$3" > /dev/null
  cat "$d/accuracy.md"
  exit 0
fi
study accuracy fine
study accuracy-ncf090 base
study accuracy-np2 base   # no kept report: the runs' wall times are in run.info (below)

echo
echo "results/accuracy-np2: wall time per run (run.info: variant seed ranks wall_s peak_kB prefix)"
for f in results/accuracy-np2/*/run.info; do printf '  %-22s %s\n' "$(basename "$(dirname "$f")")" "$(cat "$f")"; done
echo "  base seed 1, 1 rank against 2 ranks, per stage (the extracts' Loop time lines):"
"$py" - <<'EOF'
import re
def loop(path):
    return sum(float(m.group(1)) for m in
               (re.match(r"Loop time of ([0-9.eE+-]+) on", l) for l in open(path)) if m)
for st in ("compact", "pierce", "stitch", "pretension", "release"):
    one = loop(f"results/accuracy-np2/base-seed1-1rank/ncf45.{st}.extract")
    two = loop(f"results/accuracy-np2/base-seed1/ncf45.{st}.extract")
    print(f"    {st:11s} {one:8.1f} s / {two:8.1f} s = {one / two:.2f}")
EOF

echo
echo "results/accuracy/pretension-scan: loop tilt per point, seeds 1 / 2 / 3, mean ± SD"
"$py" - <<'EOF'
import csv, statistics
rows = {}
for seed in (1, 2, 3):
    for r in csv.DictReader(open(f"results/accuracy/pretension-scan/seed{seed}/scan.csv")):
        rows.setdefault((int(r["tau_steps"]), int(r["ramp_steps"]), r["ramp_over_tau"]), []).append(
            float(r["loop_tilt_deg"]))
for (tau, ramp, ratio), t in rows.items():
    print(f"  tau {tau:5d} ramp {ramp:6d} ramp/tau {ratio:>4s}: "
          + " / ".join(f"{x:.2f}" for x in t)
          + f"  {statistics.mean(t):.2f} ± {statistics.stdev(t):.2f}")
EOF

echo
echo "results/validation: the comparison with the paper (doc/validation.md, seeds 1, 2, 5 and 1-3)"
"$py" examples/manufacturing/compare_paper.py \
  --ncf090 results/validation/ncf090-seed[125]/ncf-measure-summary.csv \
  --ncf45 results/validation/ncf45-seed*/ncf-measure-summary.csv
echo "seed 1 alone:"
"$py" examples/manufacturing/compare_paper.py \
  --ncf090 results/validation/ncf090-seed1/ncf-measure-summary.csv \
  --ncf45 results/validation/ncf45-seed1/ncf-measure-summary.csv
exit $status
