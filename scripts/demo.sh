#!/usr/bin/env bash
# The main job on the embedded default scenes: installs what is missing, builds, and builds
# the gradient maps of the torus (default) and the star, writing slice pictures, .npy arrays
# and the cached maps under out/demo/.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=${BOP_JOBS:-2}

scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$jobs" --target bop-shape

for scene in torus star bag-in-bag; do
  echo "== $scene =="
  build/dynamics_server/bop-shape "config/scenes/$scene.toml" -o "out/demo/$scene" --export all
done

echo
echo "Pictures: out/demo/{torus,star,bag-in-bag}/slice-{xy,xz,yz}.png (labels, signed distance, co-planar weight)"
echo "Arrays:   out/demo/*/*.npy (NumPy shape (nz, ny, nx[, 3]); see docs/file-formats.md)"
echo "Maps:     out/demo/*/gradient-map.bopgm (cache read by the server)"
