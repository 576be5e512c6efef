#!/usr/bin/env bash
# Writes python/bop/wire/ (the Python client's FlatBuffers readers and builders) from
# protocol/schemas/*.fbs with flatc --python. The generated files are committed, so that the
# client needs no build step; ctest python.wire-generated fails when they differ from what flatc
# makes of today's schemas. Run it after changing a schema.
#   scripts/gen-python-wire.sh [OUT_DIR]   (default: python/bop/wire)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-python/bop/wire}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
s=protocol/schemas
flatc --python -o "$tmp" $s/common.fbs $s/hello.fbs $s/scene.fbs $s/frame.fbs $s/probe.fbs $s/feedback.fbs \
  $s/command.fbs $s/reply.fbs $s/refusal.fbs
rm -rf "$out"
mkdir -p "$out"
cp "$tmp"/bop/wire/*.py "$out/"
echo "gen-python-wire: $(ls "$out" | wc -l) modules in $out"
