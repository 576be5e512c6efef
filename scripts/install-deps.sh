#!/usr/bin/env bash
# Installs the Debian 12 packages BoP builds and tests with. Idempotent: packages already
# present are skipped, so a second run costs a few dpkg queries. Runs as root, or via sudo.
#   scripts/install-deps.sh           build and test dependencies
#   scripts/install-deps.sh --bench   also the peers the benchmarks compare against
#   scripts/install-deps.sh --fuzz    also Clang's libFuzzer (scripts/fuzz.sh)
set -euo pipefail

packages=(
  # toolchain; clang-format checks the sources' format (scripts/test.sh)
  build-essential cmake ninja-build pkg-config git clang-format
  # libraries (see README "Dependencies")
  libeigen3-dev libspdlog-dev libtomlplusplus-dev libcli11-dev libstb-dev
  libassimp-dev libnifti2-dev libniftiio-dev libznz-dev zlib1g-dev
  # the decomposed run (dynamics_server/parallel/)
  libopenmpi-dev openmpi-bin
  # the wire protocol and network front (protocol/)
  flatbuffers-compiler flatbuffers-compiler-dev libflatbuffers-dev libzmq3-dev cppzmq-dev
  # recordings: zstd-compressed MCAP chunks (protocol/recording/)
  libzstd-dev
  # bop-igtl (protocol/igtl/): OpenIGTLink's reference library packs its messages; the tests build
  # the library's own example clients from openigtlink-examples
  libopenigtlink-dev openigtlink-examples
  # the viewer's renderer (viz_client/): OpenGL and EGL headers and libraries (libglvnd), Mesa's
  # EGL and its llvmpipe software driver for headless rendering without a GPU
  libgl-dev libopengl-dev libegl-dev libegl-mesa0 libgl1-mesa-dri
  # the viewer's window and panel: GLFW 3.3, Dear ImGui 1.86 with its GLFW and OpenGL3 backends;
  # Xvfb and Mesa's GLX so the window path is tested without a display
  libglfw3-dev libimgui-dev xvfb xauth libglx-mesa0
  # the haptic client's 3Dconnexion adapter (spacenavd's client library)
  libspnav-dev
  # tests; the two-host tests' namespaces, veth pair, netem and datagram loss (scripts/two-host.sh);
  # ASE reads our extended XYZ files in the tests (tests/cli/bop_server_xyz_cli.sh)
  catch2 python3 python3-numpy python3-ase iproute2 nftables
  # the Python client (python/bop) and its tests: ZeroMQ, FlatBuffers, zstd-compressed recordings;
  # matplotlib draws every plot (python/bop/plots.py: bop-haptic's stiffness, the ventricle's pressure)
  python3-zmq python3-flatbuffers python3-zstandard python3-matplotlib
  # scripts/netdelay (bop-netdelay) and its iptables NFQUEUE rule: two-host.sh's delay where the kernel has no netem
  libnetfilter-queue-dev iptables
)
# the Foxglove check of recordings (tests/cli/foxglove_cli.sh) runs in Node.js with packages from
# npm: Debian's nodejs and npm, unless a Node.js with npm is already installed (another vendor's
# nodejs package holds npm itself and conflicts with Debian's npm)
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
  packages+=(nodejs npm)
fi
if [[ "${1:-}" == "--bench" ]]; then
  packages+=(python3-scipy lammps gromacs time)
fi
if [[ "${1:-}" == "--fuzz" ]]; then  # scripts/fuzz.sh: libFuzzer and sanitizer runtimes, symbolizer
  packages+=(clang libclang-rt-dev llvm)
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [[ ${#missing[@]} -eq 0 ]]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

sudo=""
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "install-deps: run as root or install sudo" >&2; exit 1; }
  sudo=sudo
fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
