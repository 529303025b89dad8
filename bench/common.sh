# Sourced by the manufacturing benches (effects.sh, scaling.sh): the build's environment, a work
# folder (kept with NCF_BENCH_KEEP=1, removed at exit otherwise), the load average, and the scene:
# stages 1-3 of a fabric run untimed once (or an earlier run's outputs, NCF_BENCH_SCENE=DIR).
# Needs: root (the repository). Sets: man, work, and with bench_scene FABRIC: scene.
man="$root/examples/manufacturing"
source "${NCF_BUILD:-$root/build}/ncf-env.sh"

bench_work() {    # name
  work=$(mktemp -d "/tmp/ncf-$1.XXXXXX")
  if [ -n "${NCF_BENCH_KEEP:-}" ]; then echo "outputs in $work"; else trap 'rm -rf "$work"' EXIT; fi
  echo "load average before the runs: $(cut -d' ' -f1-3 /proc/loadavg) on $(nproc) cores (timings are only comparable on an idle machine)"
}

bench_scene() {    # fabric
  if [ -n "${NCF_BENCH_SCENE:-}" ]; then
    scene=$(cd "$NCF_BENCH_SCENE" && pwd)
  else
    scene=$work/scene
    echo "stages 1-3 of $1 (untimed) ..."
    NCF_STAGES=1-3 bash "$man/run.sh" "$scene" "$1" > "$work/stages.out"
  fi
}
