#!/usr/bin/env bash
# The main job on the embedded default scenes: installs what is missing, builds, builds the
# gradient maps of the torus (default), the star and the bag-in-bag (slice pictures, .npy arrays,
# cached maps under out/demo/), then builds the torus bag of particles in a batch run of the
# dynamics server and writes its final state as extended XYZ.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=${BOP_JOBS:-2}

scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$jobs" --target bop-shape bop-server

for scene in torus star bag-in-bag; do
  echo "== $scene =="
  build/dynamics_server/bop-shape "config/scenes/$scene.toml" -o "out/demo/$scene" --export all
done

echo "== torus bag: construction and relaxation (bop-server batch run) =="
build/dynamics_server/bop-server config/scenes/torus.toml --no-listen -o out/demo/torus

echo
echo "Particles: out/demo/torus/final.xyz (extended XYZ; open it in OVITO)"
echo "Pictures: out/demo/{torus,star,bag-in-bag}/slice-{xy,xz,yz}.png (labels, signed distance, co-planar weight)"
echo "Arrays:   out/demo/*/*.npy (NumPy shape (nz, ny, nx[, 3]); see docs/file-formats.md)"
echo "Maps:     out/demo/*/gradient-map.bopgm (cache read by the server)"
