#!/usr/bin/env bash
# bop-shape from the command line: --help, a torus build with its report, PNG and .npy files
# that NumPy reads with the documented layout, a cache hit on the second run, and clear errors
# with a non-zero exit for bad input.
# Usage: bop_shape_cli.sh PATH/TO/bop-shape REPO_ROOT
set -u
exe=$1 repo=$2
source "$(dirname "$0")/cli-checks.sh"

bounded 30 "$work/help.txt" "$exe" --help
check "--help exits 0 and names the scene argument" "grep -q 'scene' '$work/help.txt'"

bounded 120 "$work/run1.txt" "$exe" "$repo/config/scenes/torus-analytic.toml" -o "$work/out" --export all
rc=$?
check "a torus build exits 0" "[ $rc -eq 0 ]"
check "the report gives grid size and label counts" "grep -q '^grid ' '$work/run1.txt' && grep -q 'surface' '$work/run1.txt'"
check "three slice pictures are PNG files" "[ \$(ls '$work/out'/slice-*.png | wc -l) -eq 3 ] && head -c 8 '$work/out/slice-xy.png' | grep -q PNG"
bounded 120 "$work/run2.txt" "$exe" "$repo/config/scenes/torus-analytic.toml" -o "$work/out" --export none --no-png
check "the second run reads the cache" "grep -q 'from the cache' '$work/run2.txt'"

py=/usr/bin/python3
if "$py" -c 'import numpy' 2>/dev/null; then
  bounded 60 "$work/py.txt" "$py" - "$work/out" <<'PY'
import sys, numpy as np
d = sys.argv[1]
labels = np.load(d + "/labels.npy"); vec = np.load(d + "/vectors.npy"); dist = np.load(d + "/distance.npy")
assert labels.dtype == np.uint8 and vec.dtype == np.int16 and vec.shape == labels.shape + (3,), (labels.shape, vec.shape)
surf = labels == 1
assert surf.any() and (labels == 2).any()
# Vectors are zero on surface voxels and point to a surface voxel everywhere else.
assert not vec[surf].any()
nz, ny, nx = labels.shape
k, j, i = np.indices(labels.shape)
tgt = (k + vec[..., 2], j + vec[..., 1], i + vec[..., 0])
assert (labels[tgt] == 1).all()
# |vector| is the distance; the sign says inside (-) or outside (+).
assert np.allclose(np.abs(dist), np.linalg.norm(vec.astype(float), axis=-1), atol=1e-4)
assert (dist[labels == 0] > 0).all() and (dist[labels == 2] < 0).all()
print("numpy ok", labels.shape)
PY
  check "NumPy loads labels, vectors and distance with the documented layout" "grep -q 'numpy ok' '$work/py.txt'"
  cat "$work/py.txt"
else
  echo "skip NumPy check (python3-numpy missing)"
fi

# Several bags: the report and bags.csv against the segmentation itself. Taken as the image holds
# them (boundary_smoothing_voxels = 0), each bag holds the voxels of its label (the liver's
# tumour voxels are the tumour's), the tumour lies in the liver, and two bags touch across exactly
# the faces their labels share in the image. With the labels' boundaries smoothed (the scene as
# it ships), each bag keeps its voxel count within 2%, the tumour stays in the liver and the same
# bags touch.
sed -e 's|"\.\./data/|"'"$repo"'/config/data/|' -e 's|^source = "raw"|&\nboundary_smoothing_voxels = 0|' \
  "$repo/config/scenes/organs.toml" >"$work/organs-exact.toml"
bounded 120 "$work/organs.txt" "$exe" "$repo/config/scenes/organs.toml" -o "$work/organs" --export none
check "the organs scene's report has one line per bag" "[ \$(grep -c \"^bag '\" '$work/organs.txt') -eq 4 ]"
check "the organs scene's labels are smoothed" "grep -q 'boundary smoothing: [0-9]* voxels out' '$work/organs.txt'"
bounded 120 "$work/organs-exact.txt" "$exe" "$work/organs-exact.toml" -o "$work/organs-exact" --export none
for exact in 1 0; do
  csvfile=$([ $exact = 1 ] && echo "$work/organs-exact/bags.csv" || echo "$work/organs/bags.csv")
  bounded 60 "$work/bags.txt" "$py" - "$csvfile" "$repo/config/data/organs.raw" $exact <<'PY'
import csv, sys, numpy as np
exact = sys.argv[3] == "1"
rows = {r["name"]: r for r in csv.DictReader(open(sys.argv[1]))}
img = np.fromfile(sys.argv[2], dtype=np.uint8).reshape(36, 40, 56)
label = {"liver": 1, "stomach": 2, "spleen": 3, "tumour": 4}
number = {name: int(r["bag"]) for name, r in rows.items()}
def faces(a, b):
    n = 0
    for ax in range(3):
        x = np.swapaxes(img, 0, ax)
        n += int(((x[:-1] == a) & (x[1:] == b)).sum() + ((x[:-1] == b) & (x[1:] == a)).sum())
    return n
for name, r in rows.items():
    voxels = int(r["surface_voxels"]) + int(r["volume_voxels"])
    image = int((img == label[name]).sum())
    assert voxels == image if exact else abs(voxels / image - 1) <= 0.02, (name, voxels, image)
    touching = dict(zip(map(int, r["touching_bags"].split()), map(int, r["shared_faces"].split())))
    expected = {number[o]: faces(label[name], label[o]) for o in rows
                if o != name and {name, o} != {"liver", "tumour"} and faces(label[name], label[o])}
    assert touching == expected if exact else touching.keys() == expected.keys(), (name, touching, expected)
assert int(rows["tumour"]["inside_bag"]) == number["liver"] and int(rows["liver"]["inside_bag"]) == 0
print("bags ok", {n: r["touching_bags"] for n, r in rows.items()})
PY
  check "bags.csv agrees with the image ($([ $exact = 1 ] && echo 'taken as it is: voxels, containment and shared faces' ||
    echo 'smoothed: voxels within 2%, containment and the bags touching')) per bag" "grep -q 'bags ok' '$work/bags.txt'"
  cat "$work/bags.txt"
done

bounded 30 "$work/err1.txt" "$exe" "$work/absent.toml"
rc=$?
check "a missing scene exits non-zero naming the file" "[ $rc -ne 0 ] && grep -q 'absent.toml: file not found' '$work/err1.txt'"
printf '[grid]\nvoxel_size_mm = 1.0\n[shape]\n[[shape.bag]]\nsource = "mesh"\nfile = "none.stl"\n' >"$work/bad.toml"
bounded 30 "$work/err2.txt" "$exe" "$work/bad.toml" -o "$work/bad"
rc=$?
check "a missing mesh exits non-zero naming the key" "[ $rc -ne 0 ] && grep -q 'shape.bag\[0\].file' '$work/err2.txt'"
bounded 60 "$work/err3.txt" "$exe" "$repo/config/scenes/torus-analytic.toml" -o "$work/out" --export bogus
rc=$?
check "an unknown --export array is refused" "[ $rc -ne 0 ] && grep -q \"unknown array 'bogus'\" '$work/err3.txt'"
exit $fail
