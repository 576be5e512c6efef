#!/usr/bin/env bash
# Builds the peers step.sh measures BoP against, for this CPU, from Debian's source packages,
# once, into a cache outside the tree (docs/dynamics.md, "Speed"):
#   LAMMPS (Debian's 20220106 source) with its OPT, OPENMP and INTEL packages, GCC -O3
#     -march=native, no MPI: lmp (styles table/omp, lj/cut/opt, lj/cut/intel);
#   GROMACS (Debian's 2022.5 source) with the CPU's best SIMD (AVX_512 with AVX-512, AVX2_128 on a
#     first- or second-generation Zen, AVX2_256 with other AVX2), no MPI or GPU: gmx (mixed
#     precision) and gmx_d (double).
# The cache is BOP_PEERS_DIR (default ~/.cache/bop-peers), one folder per CPU: its model and a hash
# of its instruction flags name it, so a build for one CPU is never run on another. A peer already
# built is kept; the sources are fetched once (apt-get source, after adding a deb-src entry for
# Debian's archive when there is none). It prints what it built, where and how long each took.
# What cannot be built (the source not reachable, a failed build: its log is named) is said,
# the rest goes on, and it exits 1. Never run by CI or scripts/test.sh: about 30 minutes on 2 cores.
#   scripts/bench/peers.sh            build what is missing, then print the paths
#   scripts/bench/peers.sh --print    print shell assignments of what is built, building nothing:
#                                     PEER_LMP=..., PEER_GMX=..., PEER_GMX_D=... (empty when absent)
#   scripts/bench/peers.sh --only lammps|gromacs|gromacs-double   build that one alone
# Environment: BOP_PEERS_DIR (cache), BOP_JOBS (build jobs, default 2).
set -euo pipefail
if [[ ${1:-} == -h || ${1:-} == --help ]]; then  # the comment above is the help
  sed -n '2,/^set -euo/{/^#/s/^# \{0,1\}//p}' "$0"
  exit 0
fi
root=${BOP_PEERS_DIR:-$HOME/.cache/bop-peers}
jobs=${BOP_JOBS:-2}
model=$(sed -n 's/^model name[[:space:]]*: *//p' /proc/cpuinfo | head -1)
flags=$(sed -n 's/^flags[[:space:]]*: *//p' /proc/cpuinfo | head -1)
key=$(printf '%s\n%s\n' "$model" "$flags" | sha256sum | cut -c1-12)
dir=$root/$(printf '%s' "$model" | tr -c 'A-Za-z0-9' '-' | tr -s '-' | sed 's/-$//')-$key
lmp=$dir/lammps/lmp_native gmx=$dir/gromacs/bin/gmx gmx_d=$dir/gromacs-double/bin/gmx_d

print_paths() {
  echo "PEER_DIR='$dir'"
  echo "PEER_LMP='$([[ -x $lmp ]] && echo "$lmp")'"
  echo "PEER_GMX='$([[ -x $gmx ]] && echo "$gmx")'"
  echo "PEER_GMX_D='$([[ -x $gmx_d ]] && echo "$gmx_d")'"
}
if [[ ${1:-} == --print ]]; then
  print_paths
  exit 0
fi
only=""
if [[ ${1:-} == --only ]]; then
  only=${2:-}
  [[ $only == lammps || $only == gromacs || $only == gromacs-double ]] ||
    { echo "peers: --only wants lammps, gromacs or gromacs-double (got '$only')" >&2; exit 2; }
fi

simd() {  # GROMACS's SIMD for this CPU
  local family
  family=$(sed -n 's/^cpu family[[:space:]]*: *//p' /proc/cpuinfo | head -1)
  if [[ " $flags " == *" avx512f "* ]]; then echo AVX_512
  elif [[ " $flags " == *" avx2 "* && $model == *AMD* && $family == 23 ]]; then echo AVX2_128  # Zen 1 and 2
  elif [[ " $flags " == *" avx2 "* ]]; then echo AVX2_256
  else echo SSE4.1
  fi
}

failed=()
mkdir -p "$dir/src" "$dir/logs"
echo "peers: CPU $model; cache $dir"

# fetch PACKAGE: its Debian source unpacked under $dir/src (once); prints the folder.
fetch() {
  local pkg=$1 found
  found=$(find "$dir/src" -maxdepth 1 -mindepth 1 -type d -name "$pkg-*" | head -1)
  if [[ -z $found ]]; then
    if ! apt-get source --print-uris "$pkg" >/dev/null 2>&1; then
      # No deb-src entry yet: Debian's archive, as the binary entries name it.
      local list=/etc/apt/sources.list.d/bop-deb-src.sources
      if [[ ! -e $list ]]; then
        sed -n '/^Types:/,/^$/p' /etc/apt/sources.list.d/debian.sources 2>/dev/null |
          sed 's/^Types: deb$/Types: deb-src/' >"$list" || true
        [[ -s $list ]] || printf 'Types: deb-src\nURIs: http://deb.debian.org/debian\nSuites: bookworm\nComponents: main\nSigned-By: /usr/share/keyrings/debian-archive-keyring.gpg\n' >"$list"
      fi
      apt-get update -qq >"$dir/logs/apt-update.log" 2>&1 || true
    fi
    (cd "$dir/src" && apt-get source -qq "$pkg" >"$dir/logs/source-$pkg.log" 2>&1) || return 1
    found=$(find "$dir/src" -maxdepth 1 -mindepth 1 -type d -name "$pkg-*" | head -1)
  fi
  [[ -n $found ]] && echo "$found"
}

# timed NAME LOG COMMAND...: runs it, says how long it took or where its log is.
timed() {
  local name=$1 log=$2 t0
  shift 2
  t0=$(date +%s)
  if "$@" >"$log" 2>&1; then
    echo "peers: $name built in $(($(date +%s) - t0)) s"
  else
    echo "peers: $name FAILED after $(($(date +%s) - t0)) s (log: $log)"
    failed+=("$name")
    return 1
  fi
}

apt_needs() {  # the build tools, from Debian
  local missing=()
  for p in "$@"; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
  [[ ${#missing[@]} -eq 0 ]] || DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >"$dir/logs/apt-install.log" 2>&1
}

build_lammps() {
  local src=$1
  rm -rf "$dir/lammps"
  mkdir -p "$dir/lammps"
  (cd "$dir/lammps" && cmake "$src/cmake" -DCMAKE_BUILD_TYPE=Release -DBUILD_MPI=off -DBUILD_OMP=on -DPKG_INTEL=on \
    -DPKG_OPT=on -DPKG_OPENMP=on -DINTEL_ARCH=cpu -DCMAKE_CXX_FLAGS="-O3 -march=native" -DLAMMPS_MACHINE=native &&
    make -j "$jobs")
}

build_gromacs() {  # build_gromacs SRC DIR DOUBLE(on|off): built in DIR, run from there (it finds its data in SRC)
  local src=$1 build=$2 double=$3
  rm -rf "$build"
  mkdir -p "$build"
  # rdtscp: GROMACS's timers use it unless told not to, and stop at start on a CPU (or VM) without it.
  local rdtscp=OFF
  [[ " $flags " != *" rdtscp "* ]] || rdtscp=ON
  (cd "$build" && cmake "$src" -DCMAKE_BUILD_TYPE=Release -DGMX_SIMD="$(simd)" -DGMX_DOUBLE="$double" \
    -DGMX_USE_RDTSCP="$rdtscp" \
    -DGMX_FFT_LIBRARY=fftw3 -DGMX_BUILD_OWN_FFTW=OFF -DGMX_MPI=OFF -DGMX_GPU=OFF -DGMX_HWLOC=OFF -DBUILD_TESTING=OFF &&
    make -j "$jobs" gmx)
}

apt_needs cmake g++ make dpkg-dev libfftw3-dev || echo "peers: could not install the build tools (see $dir/logs/apt-install.log)"
if [[ -z $only || $only == lammps ]]; then
  if [[ -x $lmp ]]; then echo "peers: LAMMPS already built: $lmp"
  elif src=$(fetch lammps); then timed "LAMMPS ($(basename "$src"), OPT OPENMP INTEL, -march=native)" "$dir/logs/lammps.log" build_lammps "$src" || true
  else echo "peers: LAMMPS's source package could not be fetched (see $dir/logs/)"; failed+=(LAMMPS)
  fi
fi
if [[ -z $only || $only == gromacs* ]]; then
  if src=$(fetch gromacs); then
    if [[ -z $only || $only == gromacs ]]; then
      if [[ -x $gmx ]]; then echo "peers: GROMACS (mixed) already built: $gmx"
      else timed "GROMACS mixed ($(basename "$src"), SIMD $(simd))" "$dir/logs/gromacs.log" build_gromacs "$src" "$dir/gromacs" off || true
      fi
    fi
    if [[ -z $only || $only == gromacs-double ]]; then
      if [[ -x $gmx_d ]]; then echo "peers: GROMACS (double) already built: $gmx_d"
      else timed "GROMACS double ($(basename "$src"), SIMD $(simd))" "$dir/logs/gromacs-double.log" build_gromacs "$src" "$dir/gromacs-double" on || true
      fi
    fi
  else
    echo "peers: GROMACS's source package could not be fetched (see $dir/logs/)"
    failed+=(GROMACS)
  fi
fi
print_paths
if [[ ${#failed[@]} -gt 0 ]]; then
  echo "peers: not built: ${failed[*]}" >&2
  exit 1
fi
