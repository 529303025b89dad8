#!/bin/bash
# pair ncf/contact bench (design.md section 9; issue 3 item 6). Prints the cost per node per step of
# pair ncf/contact on a compacted fibrous mat (69 um chains, 0.2 mm mesh, Vf 0.45, >= 20 000 nodes)
# relative to LAMMPS pair gran/hooke/history on a sphere packing with the same number of particles
# and a comparable number of contacts, and the 1 -> 2 rank speed-up of the mat.
# Usage: bench/run.sh [steps]   (after tools/setup.sh; uses build/ncf-env.sh)
# NCF_BENCH_REPS=n: repetitions of the timed runs (default 5); NCF_BENCH_KEEP=1 keeps the logs
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
source "${NCF_BUILD:-$root/build}/ncf-env.sh"
steps=${1:-100}
work=$(mktemp -d /tmp/ncf-bench.XXXXXX)
[ -n "${NCF_BENCH_KEEP:-}" ] || trap 'rm -rf "$work"' EXIT    # NCF_BENCH_KEEP=1 keeps the logs
cd "$work"
mpirun=(mpirun --oversubscribe)
[ "$(id -u)" = 0 ] && mpirun+=(--allow-run-as-root)

echo "load average before the runs: $(cut -d' ' -f1-3 /proc/loadavg) on $(nproc) cores (timings are only comparable on an idle machine)"
python3 "$here/make_mat.py" mat.data --side 6e-3 --layers 16 --vf 0.45 | tee make.log
nodes=$(awk '/ atoms$/{print $1; exit}' mat.data)
# untimed: the geometric mat settles between the plates into a compacted mat at rest (~45 s)
relax=${NCF_BENCH_RELAX:-2000}
lmp -in "$here/in.relax" -var bench "$here" -var data mat.data -var relax "$relax" -var out mat.restart -log relax.log -screen none
awk '/^ *Step/{f=1;next} f&&$1~/^[0-9]+$/{l=$0} /^Loop time/{f=0} END{split(l,c); printf "relaxed %d steps: %s contacting segment pairs, rms node speed %.2f m/s\n", c[1], c[4], c[6]}' relax.log
# sphere packing with about the same number of particles
side=$(python3 -c "import math; print(round(math.sqrt($nodes/30)))")
nz=$(python3 -c "print(round($nodes/($side*$side)))")

loop() { awk '/^Loop time of/{t=$4} END{print t}' "$1"; }
pairt() { awk '/^Pair  *\|/{t=$3} END{print t}' "$1"; }
grains_of() { awk '/^Loop time of/{n=$NF=="atoms"?$(NF-1):n} END{print n}' "$1"; }
contacts() { awk -v col="$2" 'f&&NF>=col&&$1~/^[0-9]+$/{c=$col} /^ *Step/{f=1} END{print c}' "$1"; }

# The timed runs, repeated (NCF_BENCH_REPS, default 5) and interleaved, so that a slow spell of a
# shared machine hits every kind alike; each kind is timed by its fastest repetition (the run least
# disturbed), and the ratio of every single repetition is printed as well to show the scatter
reps=${NCF_BENCH_REPS:-5}
# the spheres are ~6 times cheaper per step: 5 times the steps, so that both are timed over about
# the same wall time
gsteps=$((5 * steps))
ncf() { lmp -in "$here/in.ncf" -var bench "$here" -var restart mat.restart -var mu "$1" -var steps "$steps" -var frozen "${3:-0}" -var law "${4:-symmetric}" -log "$2" -screen none; }
for r in $(seq "$reps"); do
  # the speed-up and the machine's ceiling first, back to back, so that both see the same state of
  # a machine whose speed changes within seconds
  ncf 0.3 ncf1.$r.log
  for b in 0 1; do    # 2 ranks: LAMMPS's even split of the box, then cut by the work estimate
    "${mpirun[@]}" -np 2 lmp -in "$here/in.ncf" -var bench "$here" -var restart mat.restart -var mu 0.3 -var steps "$steps" -var balance $b -log ncf2$([ $b = 1 ] && echo b).$r.log -screen none
  done
  # the machine's own ceiling for 2 ranks: two independent 1-rank runs side by side, one per core
  # (shared caches, memory bandwidth and clock make each slower than a run alone; no MPI at all)
  ncf 0.3 twinA.$r.log & ncf 0.3 twinB.$r.log; wait
  lmp -in "$here/in.gran" -var nx "$side" -var ny "$side" -var nz "$nz" -var steps "$gsteps" -log gran1.$r.log -screen none
  ncf 0.0 ncf1mu0.$r.log
  # the same configuration every step, with and without friction (the saving of mu = 0 alone)
  ncf 0.3 frozen.$r.log 1
  ncf 0.0 frozenmu0.$r.log 1
  # the one-way contact law (pair_style ncf/contact law oneway)
  ncf 0.3 oneway.$r.log 0 oneway
  r1=$(loop ncf1.$r.log) r2=$(loop ncf2.$r.log) r2b=$(loop ncf2b.$r.log) rg=$(loop gran1.$r.log) gn=$(grains_of gran1.$r.log)
  ta=$(loop twinA.$r.log) tb=$(loop twinB.$r.log)
  python3 -c "print(f'repetition $r: cost ratio {($r1 / $nodes / $steps) / ($rg / $gn / $gsteps):.2f}; 1->2 rank speed-up {$r1 / $r2b:.2f} balanced by the work estimate, {$r1 / $r2:.2f} even split; two 1-rank runs side by side take {max($ta, $tb) / $r1:.2f} x as long as one alone, machine ceiling {2 * $r1 / max($ta, $tb):.2f}, the balanced 2-rank run {100 * max($ta, $tb) / (2 * $r2b):.0f} % of it')"
done
# the fastest repetition of each kind
fastest() { for f in "$@"; do echo "$(loop "$f") $f"; done | sort -g | head -1 | cut -d' ' -f2; }
f1=$(fastest ncf1.*.log); f2=$(fastest ncf2.*.log); f2b=$(fastest ncf2b.*.log); f0=$(fastest ncf1mu0.*.log); fg=$(fastest gran1.*.log)
fz=$(fastest frozen.*.log); fz0=$(fastest frozenmu0.*.log); fo=$(fastest oneway.*.log)
# (the side-by-side pair timed by its slower run, the pair of the fastest such repetition)
ftw=$(for r in $(seq "$reps"); do echo "$(printf '%s\n%s\n' "$(loop twinA.$r.log)" "$(loop twinB.$r.log)" | sort -g | tail -1) $r"; done | sort -g | head -1 | cut -d' ' -f2)
ttw=$(printf '%s\n%s\n' "$(loop twinA.$ftw.log)" "$(loop twinB.$ftw.log)" | sort -g | tail -1)
grains=$(grains_of "$fg")

t1=$(loop "$f1"); t2=$(loop "$f2"); t2b=$(loop "$f2b"); t0=$(loop "$f0"); tg=$(loop "$fg")
p1=$(pairt "$f1"); p0=$(pairt "$f0"); pg=$(pairt "$fg")
tz=$(loop "$fz"); tz0=$(loop "$fz0"); pz=$(pairt "$fz"); pz0=$(pairt "$fz0"); to=$(loop "$fo")
c_ncf=$(contacts "$f1" 4); c_gran=$(contacts "$fg" 3)
builds() { awk '/^Neighbor list builds/{n=$NF} END{print n}' "$1"; }
# (without friction the mat relaxed with friction slides a little: a few builds in the mu = 0 run)
echo "list builds in the timed steps: ncf/contact $(builds "$f1") (2 ranks $(builds "$f2"), mu = 0 $(builds "$f0")), gran/hooke/history $(builds "$fg")"
python3 - "$nodes" "$grains" "$steps" "$gsteps" "$t1" "$t2" "$t0" "$tg" "$p1" "$p0" "$pg" "$c_ncf" "$c_gran" "$tz" "$tz0" "$pz" "$pz0" "$to" "$ttw" "$t2b" "$(for r in $(seq "$reps"); do echo "$(loop ncf1.$r.log) $(loop ncf2b.$r.log) $(loop twinA.$r.log) $(loop twinB.$r.log)"; done | tr '\n' ';')" <<'PY'
import sys
nodes, grains, steps, gsteps = map(int, sys.argv[1:5])
t1, t2, t0, tg, p1, p0, pg = map(float, sys.argv[5:12])
c_ncf, c_gran = float(sys.argv[12]), float(sys.argv[13]) / 2.0   # contact/atom counts each contact twice
tz, tz0, pz, pz0, to, ttw, t2b = map(float, sys.argv[14:21])
# per repetition: 1-rank, balanced 2-rank and the two side-by-side runs; the medians of each one's
# own speed-up and of its share of its own ceiling
reps = [list(map(float, r.split())) for r in sys.argv[21].split(';') if r.strip()]
median = lambda v: sorted(v)[len(v) // 2] if len(v) % 2 else 0.5 * sum(sorted(v)[len(v) // 2 - 1:len(v) // 2 + 1])
sp_med = median([a / b for a, b, _, _ in reps])
share_med = median([max(ta, tb) / (2.0 * b) for _, b, ta, tb in reps])
per = lambda t, n, k=steps: t / (n * k) * 1e6
print(f"mat: {nodes} nodes, {c_ncf:.0f} contacting segment pairs ({c_ncf / nodes:.2f} per node) at the end")
print(f"spheres: {grains} particles, {c_gran:.0f} contacts ({c_gran / grains:.2f} per particle)")
print(f"cost per node per step [us]: ncf/contact {per(t1, nodes):.3f} (pair {per(p1, nodes):.3f}), "
      f"mu=0 {per(t0, nodes):.3f} (pair {per(p0, nodes):.3f}), gran/hooke/history {per(tg, grains, gsteps):.3f} (pair {per(pg, grains, gsteps):.3f})")
print(f"mu = 0 (no history stored or communicated), same configuration every step: pair {100 * (1 - pz0 / pz):.1f} % cheaper, "
      f"whole step {100 * (1 - tz0 / tz):.1f} % cheaper; in the moving mat, which slides without friction: "
      f"whole step {100 * (1 - t0 / t1):.1f} % cheaper")
ratio = per(t1, nodes) / per(tg, grains, gsteps)
print(f"ncf/contact vs gran/hooke/history cost ratio: {ratio:.2f}; 1->2 rank speed-up: {t1 / t2b:.2f} "
      f"(sub-domains balanced by the work estimate; {t1 / t2:.2f} with the even split; median of the "
      f"repetitions' own speed-ups {sp_med:.2f})")
# what 2 cores of this machine give at best: two independent 1-rank runs at once (no MPI)
ceil = 2.0 * t1 / ttw
print(f"machine ceiling (two 1-rank runs side by side): {ceil:.2f}; the 2-rank run reaches {100 * (t1 / t2b) / ceil:.0f} % of it "
      f"(median over the repetitions of each one's share of its own ceiling: {100 * share_med:.0f} %)")
print(f"one-way contact law (law oneway): cost ratio {per(to, nodes) / per(tg, grains, gsteps):.2f}, "
      f"{100 * (1 - to / t1):.1f} % cheaper than the symmetric law")
PY
