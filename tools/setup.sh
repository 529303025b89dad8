#!/usr/bin/env bash
# USER-NCF set-up: everything the main job and the tests need, from a bare Debian 12 machine.
#
#   1. Debian packages (compiler, cmake, ninja, Open MPI, FFTW, Eigen, GoogleTest, image libs, numpy,
#      matplotlib) are installed when one is missing (needs root; otherwise it says what to install).
#   2. The LAMMPS source: $NCF_LAMMPS_SRC if set (your own tree, the folder holding src/ and cmake/),
#      else a Debian source package "lammps" fetched through this machine's configured Debian
#      mirror, its orig tarball checked against a fixed sha256. NCF_LAMMPS picks the version:
#        2025 (default)  20250204+dfsg.1 from trixie = LAMMPS 4 Feb 2025
#        2026            20260704+dfsg from sid      = LAMMPS 4 Jul 2026
#   3. LAMMPS is built as a shared library (MPI, PLUGIN, MOLECULE, EXTRA-FIX, GRANULAR, JPEG, PNG,
#      and GRAPHICS in the versions where dump image lives in that package) into a cache outside
#      the repository ($NCF_CACHE, default ~/.cache/user-ncf), keyed by the LAMMPS version and a
#      hash of the configuration; a matching build is reused, never rebuilt.
#   4. The plugin (ncfplugin.so), the generator and the tests are built in $NCF_BUILD (default
#      ./build for 2025, ./build-lammps2026 for 2026, see tools/ncf-lammps.sh).
#
# The CMake configure of step 4 writes $NCF_BUILD/ncf-env.sh, which the other scripts source.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
source "$here/tools/ncf-lammps.sh"
cache=${NCF_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/user-ncf}
build=${NCF_BUILD:-$here/$ncf_default_build}
jobs=${NCF_JOBS:-$(nproc)}

# the Debian source package of each supported version: version, suite, orig tarball, its sha256,
# and the folder it is unpacked into under $cache/src
case $ncf_lammps in
  2025)
    LAMMPS_DEB_VERSION="20250204+dfsg.1"
    LAMMPS_SUITE=trixie
    LAMMPS_TARBALL="lammps_${LAMMPS_DEB_VERSION}.orig.tar.xz"
    LAMMPS_SHA256="3671165bd52fad36734e0a9136c5bc5ecb225e03988f8c89aa13366a8b53b1c7"
    LAMMPS_TOPDIR="lammps-4Feb2025"
    ;;
  2026)
    LAMMPS_DEB_VERSION="20260704+dfsg"
    LAMMPS_SUITE=sid
    LAMMPS_TARBALL="lammps_${LAMMPS_DEB_VERSION}.orig.tar.gz"
    LAMMPS_SHA256="cddbc45a047416bd48a4a0b87f24a5b61b3446982b74d18cafe619c22b17eb62"
    LAMMPS_TOPDIR="lammps-4Jul2026"
    ;;
esac

say() { printf '[ncf-setup] %s\n' "$*"; }
die() {
  printf '[ncf-setup] ERROR: %s\n' "$*" >&2
  exit 1
}

# ---------------------------------------------------------------- 1. Debian packages
deb_packages=(build-essential cmake ninja-build git xz-utils ca-certificates pkg-config
  libopenmpi-dev openmpi-bin libfftw3-dev libeigen3-dev libgtest-dev libgmock-dev
  libyaml-dev libjpeg-dev libpng-dev zlib1g-dev python3 python3-numpy python3-scipy python3-matplotlib
  python3-vtk9 python3-meshio)

missing=()
for p in "${deb_packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if ((${#missing[@]})); then
  if [ "$(id -u)" -ne 0 ]; then
    die "missing Debian packages: ${missing[*]} (run as root, or: sudo apt-get install ${missing[*]})"
  fi
  say "installing Debian packages: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# ---------------------------------------------------------------- 2. LAMMPS source
fetch_debian_source() {
  local dest=$1 work uri
  work=$(mktemp -d)
  chmod 755 "$work"    # apt downloads as user _apt
  # the mirror this machine already uses for bookworm, asked for the source package of $LAMMPS_SUITE
  uri=$( { grep -hsE '^URIs:' /etc/apt/sources.list.d/*.sources || true
    grep -hsE '^deb ' /etc/apt/sources.list /etc/apt/sources.list.d/*.list || true; } |
    awk '{for (i = 2; i <= NF; i++) if ($i ~ /^[a-z]+:\/\//) {print $i; exit}}' |
    grep -E '/debian/?$' | head -n 1 || true)
  [ -n "$uri" ] || die "no Debian mirror found in /etc/apt/sources.list*; set NCF_LAMMPS_SRC to a LAMMPS source tree"
  mkdir -p "$work/lists/partial" "$work/dl"
  echo "deb-src [trusted=yes] $uri $LAMMPS_SUITE main" >"$work/src.list"
  local o=(-o "Dir::Etc::SourceList=$work/src.list" -o Dir::Etc::SourceParts=/dev/null
    -o "Dir::State::Lists=$work/lists")
  say "fetching the Debian source package lammps ($LAMMPS_DEB_VERSION, suite $LAMMPS_SUITE) through the configured mirror"
  apt-get "${o[@]}" update -qq || die "apt-get update for the $LAMMPS_SUITE sources failed"
  # apt may complain about a missing .dsc; the orig tarball still arrives and is checked below
  (cd "$work/dl" && apt-get "${o[@]}" source --download-only lammps >/dev/null 2>&1) || true
  [ -f "$work/dl/$LAMMPS_TARBALL" ] ||
    die "the LAMMPS tarball $LAMMPS_TARBALL did not arrive (the suite $LAMMPS_SUITE may have moved on to another version; set NCF_LAMMPS_SRC to a LAMMPS source tree)"
  mv "$work/dl/$LAMMPS_TARBALL" "$dest"
  rm -rf "$work"
}

if [ -n "${NCF_LAMMPS_SRC:-}" ]; then
  lmp_top=$(cd "$NCF_LAMMPS_SRC" && pwd)
  [ -f "$lmp_top/src/version.h" ] && [ -f "$lmp_top/cmake/CMakeLists.txt" ] ||
    die "NCF_LAMMPS_SRC=$NCF_LAMMPS_SRC is not a LAMMPS source tree (no src/version.h or cmake/CMakeLists.txt)"
  origin="custom:$lmp_top"
else
  mkdir -p "$cache/src"
  lmp_top="$cache/src/$LAMMPS_TOPDIR"
  if [ ! -f "$lmp_top/.ncf-unpacked" ]; then
    tarball="$cache/src/$LAMMPS_TARBALL"
    [ -f "$tarball" ] || fetch_debian_source "$tarball"
    sum=$(sha256sum "$tarball" | awk '{print $1}')
    if [ "$sum" != "$LAMMPS_SHA256" ]; then
      rm -f "$tarball"
      die "checksum mismatch for $LAMMPS_TARBALL: got $sum, want $LAMMPS_SHA256"
    fi
    say "unpacking $LAMMPS_TARBALL (sha256 verified)"
    rm -rf "$lmp_top" "$lmp_top.unpack"
    mkdir -p "$lmp_top.unpack"
    tar --no-same-owner -C "$lmp_top.unpack" -xf "$tarball"
    # the 2025 tarball holds one top folder, the 2026 one the tree itself
    top=("$lmp_top.unpack"/*)
    if [ ${#top[@]} -eq 1 ] && [ -d "${top[0]}" ]; then
      mv "${top[0]}" "$lmp_top" && rmdir "$lmp_top.unpack"
    else
      mv "$lmp_top.unpack" "$lmp_top"
    fi
    [ -f "$lmp_top/src/version.h" ] || die "$LAMMPS_TARBALL did not unpack into a LAMMPS tree"
    touch "$lmp_top/.ncf-unpacked"
  fi
  origin="debian:$LAMMPS_DEB_VERSION:$LAMMPS_SHA256"
fi
lmp_version=$(sed -n 's/^#define LAMMPS_VERSION "\(.*\)"/\1/p' "$lmp_top/src/version.h" | tr -d ' ')

# ---------------------------------------------------------------- 3. LAMMPS build (cached)
lmp_cmake_opts=(-G Ninja -DCMAKE_BUILD_TYPE=Release -DBUILD_SHARED_LIBS=on -DBUILD_MPI=on
  -DBUILD_OMP=off -DLAMMPS_SIZES=smallbig -DPKG_PLUGIN=on -DPKG_MOLECULE=on -DPKG_EXTRA-FIX=on
  -DPKG_GRANULAR=on -DWITH_JPEG=on -DWITH_PNG=on -DWITH_GZIP=on -DWITH_FFMPEG=off
  -DFFT=FFTW3 -DBUILD_TOOLS=off -DCMAKE_INSTALL_LIBDIR=lib)
# dump image (and with it the JPEG/PNG options) moved into the GRAPHICS package after 4 Feb 2025;
# the examples draw pictures, so it is enabled where it exists (the 2025 key stays as it was)
if [ -d "$lmp_top/src/GRAPHICS" ]; then lmp_cmake_opts+=(-DPKG_GRAPHICS=on); fi
compiler=$(c++ --version | head -n 1)
mpiver=$(mpirun --version 2>/dev/null | head -n 1 || true)
key_text="$origin|${lmp_cmake_opts[*]}|$compiler|$mpiver"
key=$(printf '%s' "$key_text" | sha256sum | cut -c1-12)
lmp_prefix="$cache/lammps-$lmp_version-$key"

if [ -f "$lmp_prefix/.ncf-complete" ]; then
  say "reusing cached LAMMPS $lmp_version build: $lmp_prefix"
else
  say "building LAMMPS $lmp_version into $lmp_prefix (about 5 minutes on 2 free cores for 4 Feb 2025, a little more for later versions)"
  rm -rf "$lmp_prefix"
  mkdir -p "$lmp_prefix"
  printf '%s\n' "$key_text" >"$lmp_prefix/config.txt"
  cmake -S "$lmp_top/cmake" -B "$lmp_prefix/build" "${lmp_cmake_opts[@]}" \
    -DCMAKE_INSTALL_PREFIX="$lmp_prefix/install" >"$lmp_prefix/configure.log" 2>&1 ||
    die "LAMMPS configure failed, see $lmp_prefix/configure.log"
  cmake --build "$lmp_prefix/build" -j "$jobs" >"$lmp_prefix/build.log" 2>&1 ||
    die "LAMMPS build failed, see $lmp_prefix/build.log"
  cmake --install "$lmp_prefix/build" >"$lmp_prefix/install.log" 2>&1 ||
    die "LAMMPS install failed, see $lmp_prefix/install.log"
  touch "$lmp_prefix/.ncf-complete"
fi

# ---------------------------------------------------------------- 4. the plugin, tools, tests
say "building USER-NCF in $build"
mkdir -p "$build"
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DLAMMPS_SOURCE_DIR="$lmp_top/src" -DLAMMPS_ROOT="$lmp_prefix/install" >"$build/configure.log" 2>&1 ||
  { cat "$build/configure.log" >&2; die "configuring USER-NCF failed"; }
cmake --build "$build" -j "$jobs" || die "building USER-NCF failed"

# CMake wrote ncf-env.sh at configure time (PATH to lmp and the tools, LD_LIBRARY_PATH,
# LAMMPS_PLUGIN_PATH), so a plain CMake build has it too
[ -f "$build/ncf-env.sh" ] || die "the configure did not write $build/ncf-env.sh"
say "ready: source $build/ncf-env.sh (LAMMPS $lmp_version: lmp, ncfplugin.so, LAMMPS_PLUGIN_PATH)"
