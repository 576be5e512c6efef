#!/usr/bin/env bash
# The extended XYZ files of a construction run in the tools users have: the torus built by births
# (ids of births and seeds, not only placed ones) for 3,000 steps with a snapshot every 1,000 (the volume is seeded at step 1,500).
# final.xyz and trajectory.xyz fit the extended XYZ specification (extxyz_spec.py, which must
# refuse a copy with a column cut off), and ASE (python3-ase) reads every frame with the ids,
# species names, species numbers and positions the file holds, every id unique and below 2^31
# (ASE 3.22 reads integer columns as 32-bit integers: larger ids would come out wrong),
# the same particles under the same ids in the last frame of the trajectory and in final.xyz.
# Usage: bop_server_xyz_cli.sh PATH/TO/bop-server SOURCE_DIR
set -u
exe=$1 src=$2
source "$(dirname "$0")/cli-checks.sh"
py=/usr/bin/python3

bounded 150 "$work/run.log" "$exe" "$src/config/scenes/torus.toml" --no-listen --steps 3000 --snapshot-every 1000 \
  --cache "$work/map.bopgm" -o "$work/t"
rc=$?
check "the construction run ends (exit $rc)" "[ $rc -eq 0 ] && [ -s '$work/t/final.xyz' ] && [ -s '$work/t/trajectory.xyz' ]"
bounded 60 "$work/spec.txt" "$py" "$(dirname "$0")/extxyz_spec.py" "$work/t/final.xyz" "$work/t/trajectory.xyz"
rc=$?
cat "$work/spec.txt"
check "final.xyz and trajectory.xyz fit the extended XYZ specification" "[ $rc -eq 0 ]"
awk 'NR == 3 {NF--} {print}' "$work/t/final.xyz" >"$work/cut.xyz"
bounded 60 "$work/cut.txt" "$py" "$(dirname "$0")/extxyz_spec.py" "$work/cut.xyz"
check "... and the check refuses a copy with a column cut off" "grep -q 'line 3: .* columns' '$work/cut.txt'"

bounded 120 "$work/ase.txt" "$py" - "$work/t" <<'PY'
import sys
import ase.io

def raw(path):  # every frame as written: (step, types, numbers, ids, positions), read as text
    lines, frames, i = open(path).read().split("\n"), [], 0
    while i < len(lines) and lines[i].strip():
        n = int(lines[i])
        props = [w for w in lines[i + 1].split() if w.startswith("Properties=")][0][11:].split(":")
        names = props[0::3]
        assert names == ["type", "pos", "velo", "normal", "orientation", "omega", "id", "Z"], names
        step = int([w for w in lines[i + 1].split() if w.startswith("Step=")][0][5:])
        rows = [l.split() for l in lines[i + 2:i + 2 + n]]
        frames.append((step, [r[0] for r in rows], [int(r[-1]) for r in rows], [int(r[-2]) for r in rows],
                       [[float(x) for x in r[1:4]] for r in rows]))
        i += n + 2
    return frames

out = sys.argv[1]
for name in ("final.xyz", "trajectory.xyz"):
    atoms, frames = ase.io.read(f"{out}/{name}", index=":"), raw(f"{out}/{name}")
    assert len(atoms) == len(frames) >= 1, (name, len(atoms), len(frames))
    for a, (step, types, numbers, ids, pos) in zip(atoms, frames):
        assert a.info["Step"] == step
        assert list(a.arrays["type"]) == types
        assert list(a.numbers) == numbers
        assert [int(x) for x in a.arrays["id"]] == ids
        assert (a.positions == pos).all()
        # unique, and below 2^31: ASE 3.22 reads integer columns as 32-bit integers
        assert len(set(ids)) == len(ids) and 0 < min(ids) and max(ids) < 2 ** 31, name
    print(f"{name}: {len(atoms)} frame(s), steps {[f[0] for f in frames]}, {len(frames[-1][3])} particles, "
          f"ids {min(frames[-1][3])} to {max(frames[-1][3])}, species {sorted(set(frames[-1][1]))}")
final, last = raw(f"{out}/final.xyz")[-1], raw(f"{out}/trajectory.xyz")[-1]
assert final[0] == last[0] and sorted(final[3]) == sorted(last[3])
print("ase ok")
PY
cat "$work/ase.txt"
check "ASE reads every frame of final.xyz and trajectory.xyz with the file's ids, names, numbers and positions" \
  "grep -q 'ase ok' '$work/ase.txt'"
exit $fail
