#!/usr/bin/env bash
# USER-NCF set-up: everything the main job and the tests need, from a bare Debian 12 machine.
#
#   1. Debian packages (compiler, cmake, ninja, Open MPI, FFTW, Eigen, GoogleTest, image libs, numpy,
#      matplotlib) are installed when one is missing (needs root; otherwise it says what to install).
#   2. The LAMMPS source: $NCF_LAMMPS_SRC if set (your own tree, the folder holding src/ and cmake/),
#      else the Debian source package "lammps" 20250204+dfsg.1 (LAMMPS 4 Feb 2025) fetched through
#      this machine's configured Debian mirror, its orig tarball checked against a fixed sha256.
#   3. LAMMPS is built as a shared library (MPI, PLUGIN, MOLECULE, EXTRA-FIX, GRANULAR, JPEG, PNG)
#      into a cache outside the repository ($NCF_CACHE, default ~/.cache/user-ncf), keyed by the
#      LAMMPS version and a hash of the configuration; a matching build is reused, never rebuilt.
#   4. The plugin (ncfplugin.so), the generator and the tests are built in $NCF_BUILD (default
#      ./build).
#
# It ends by writing $NCF_BUILD/ncf-env.sh, which the other scripts source.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cache=${NCF_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/user-ncf}
build=${NCF_BUILD:-$here/build}
jobs=${NCF_JOBS:-$(nproc)}

LAMMPS_DEB_VERSION="20250204+dfsg.1"
LAMMPS_TARBALL="lammps_${LAMMPS_DEB_VERSION}.orig.tar.xz"
LAMMPS_SHA256="3671165bd52fad36734e0a9136c5bc5ecb225e03988f8c89aa13366a8b53b1c7"
LAMMPS_TOPDIR="lammps-4Feb2025"

say() { printf '[ncf-setup] %s\n' "$*"; }
die() {
  printf '[ncf-setup] ERROR: %s\n' "$*" >&2
  exit 1
}

# ---------------------------------------------------------------- 1. Debian packages
deb_packages=(build-essential cmake ninja-build git xz-utils ca-certificates pkg-config
  libopenmpi-dev openmpi-bin libfftw3-dev libeigen3-dev libgtest-dev libgmock-dev
  libyaml-dev libjpeg-dev libpng-dev zlib1g-dev python3 python3-numpy python3-scipy python3-matplotlib)

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
  # the mirror this machine already uses for bookworm, asked for trixie's source package
  uri=$( { grep -hsE '^URIs:' /etc/apt/sources.list.d/*.sources || true
    grep -hsE '^deb ' /etc/apt/sources.list /etc/apt/sources.list.d/*.list || true; } |
    awk '{for (i = 2; i <= NF; i++) if ($i ~ /^[a-z]+:\/\//) {print $i; exit}}' |
    grep -E '/debian/?$' | head -n 1 || true)
  [ -n "$uri" ] || die "no Debian mirror found in /etc/apt/sources.list*; set NCF_LAMMPS_SRC to a LAMMPS source tree"
  mkdir -p "$work/lists/partial" "$work/dl"
  echo "deb-src [trusted=yes] $uri trixie main" >"$work/src.list"
  local o=(-o "Dir::Etc::SourceList=$work/src.list" -o Dir::Etc::SourceParts=/dev/null
    -o "Dir::State::Lists=$work/lists")
  say "fetching the Debian source package lammps ($LAMMPS_DEB_VERSION) from $uri (suite trixie)"
  apt-get "${o[@]}" update -qq || die "apt-get update for the trixie sources failed"
  # apt may complain about a missing .dsc; the orig tarball still arrives and is checked below
  (cd "$work/dl" && apt-get "${o[@]}" source --download-only lammps >/dev/null 2>&1) || true
  [ -f "$work/dl/$LAMMPS_TARBALL" ] || die "the LAMMPS tarball $LAMMPS_TARBALL did not arrive"
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
    rm -rf "$lmp_top"
    tar --no-same-owner -C "$cache/src" -xf "$tarball"
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
compiler=$(c++ --version | head -n 1)
mpiver=$(mpirun --version 2>/dev/null | head -n 1 || true)
key_text="$origin|${lmp_cmake_opts[*]}|$compiler|$mpiver"
key=$(printf '%s' "$key_text" | sha256sum | cut -c1-12)
lmp_prefix="$cache/lammps-$lmp_version-$key"

if [ -f "$lmp_prefix/.ncf-complete" ]; then
  say "reusing cached LAMMPS $lmp_version build: $lmp_prefix"
else
  say "building LAMMPS $lmp_version into $lmp_prefix (about 4-5 minutes on 2 cores)"
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

cat >"$build/ncf-env.sh" <<EOF
# written by tools/setup.sh
export NCF_ROOT="$here"
export NCF_BUILD="$build"
export LAMMPS_PREFIX="$lmp_prefix/install"
export PATH="$lmp_prefix/install/bin:$build:\$PATH"
export LD_LIBRARY_PATH="$lmp_prefix/install/lib\${LD_LIBRARY_PATH:+:\$LD_LIBRARY_PATH}"
export LAMMPS_PLUGIN_PATH="$build"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
EOF
say "ready: source $build/ncf-env.sh (lmp, ncfplugin.so, LAMMPS_PLUGIN_PATH)"
