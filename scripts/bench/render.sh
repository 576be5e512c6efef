#!/usr/bin/env bash
# The viewer's renderer alone: ms per frame against particle count (synthetic torus bags of about
# 10k, 100k and 1M particles, 1280x720), drawn headless through EGL into an offscreen target and
# finished (glFinish) before the clock stops. On this project's machines that is Mesa's llvmpipe
# on the CPU, for reference; on a machine with a GPU and its EGL driver the same script measures
# the GPU.
#   scripts/bench/render.sh                      (CSV in out/bench/render.csv)
#   BOP_RENDER_SIZES="10000,100000"              particle counts
#   BOP_RENDER_FRAMES=10                         frames per count (the median is reported)
set -euo pipefail
cd "$(dirname "$0")/../.."
scripts/install-deps.sh >/dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DBOP_BUILD_VIEWER=ON >/dev/null
cmake --build build -j "${BOP_JOBS:-2}" --target bop-render-bench >/dev/null
mkdir -p out/bench
csv=out/bench/render.csv
echo "particles,surfels,spheres,build_ms,draw_ms,frame_ms,fps,renderer" >"$csv"
renderer=""
while read -r line; do
  echo "$line"
  if [[ $line == renderer* ]]; then renderer=${line#renderer }; continue; fi
  # "particles P surfels S spheres V build_ms B draw_ms D frame_ms F fps R"
  read -r _ p _ s _ v _ b _ d _ f _ r <<<"$line"
  echo "$p,$s,$v,$b,$d,$f,$r,\"$renderer\"" >>"$csv"
done < <(build/viz_client/bop-render-bench --particles "${BOP_RENDER_SIZES:-10000,100000,1000000}" \
           --frames "${BOP_RENDER_FRAMES:-10}")
echo "render: CSV in $csv"
