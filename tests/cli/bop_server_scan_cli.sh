#!/usr/bin/env bash
# The synthetic scan (scripts/make-scan-image.py, config/scenes/scan.toml): the shipped image is
# the script's output byte for byte; bop-server reads it as a NIfTI label image at 1 x 1 x 1.5 mm
# (a grid of 1 mm voxels), makes one bag per label from the label table, smooths the labels'
# staircases keeping each organ's volume within 2%, skips the speck too small
# for a bag with a warning naming it, names the thin-walled stomach, the vessel tree and the
# adrenal plates as thin, places every bag and settles them by the minimiser and the dynamics,
# every bag's particles mostly inside it, each bag's median normal angle bracketing the whole's
# (227,223 particles: about 80 s at one thread).
# Usage: bop_server_scan_cli.sh PATH/TO/bop-server SOURCE_DIR
set -u
exe=$1
src=$2
source "$(dirname "$0")/cli-checks.sh"
/usr/bin/python3 "$src/scripts/make-scan-image.py" "$work/image" >"$work/image.txt"
check "the script writes the shipped image and label table byte for byte" \
  "cmp -s '$work/image/scan.nii.gz' '$src/config/data/scan.nii.gz' && \
   cmp -s '$work/image/scan-labels.txt' '$src/config/data/scan-labels.txt'"
check "the script names 22 labels at 1 x 1 x 1.5 mm" \
  "grep -q 'voxels of 1 x 1 x 1.5 mm, 22 labels' '$work/image.txt'"

bounded 400 "$work/place.log" "$exe" "$src/config/scenes/scan.toml" --no-listen \
  --cache "$work/scan.bopgm" -o "$work/place"
rc=$?
check "the scan is mapped, placed and settled (exit $rc) on a grid of 1 mm voxels" \
  "[ $rc -eq 0 ] && grep -q 'grid [0-9]* x [0-9]* x [0-9]* voxels of 1 mm' '$work/place.log'"
check "the speck of label 23 is skipped, named with its voxel count" \
  "grep -q \"label 23 ('marker') has [0-9]* voxels, fewer than .* skipped\" '$work/place.log'"
smoothing=$(sed -n 's/.*boundary smoothing: \(.*\)/\1/p' "$work/place.log")
check "the label boundaries are smoothed, every organ's volume kept within 2% ($smoothing)" \
  "echo '$smoothing' | awk '/voxels out/ {v = \$0; sub(/.*largest volume change /, \"\", v); sub(/%.*/, \"\", v);
     out = \$1; found = 1} END {exit !(found && out > 0 && v + 0 <= 2 && v + 0 >= -2)}'"
bags=$(grep -o '[a-z_A-Z0-9]*-surface [0-9]* (' "$work/place.log" | wc -l)
check "21 bags, each named from the label table, placed on the map ($bags)" \
  "[ $bags -eq 21 ] && grep -q 'stomach-surface [0-9]* (' '$work/place.log' && grep -q 'vertebra_L4-volume' '$work/place.log'"
for thin in stomach mesenteric_vessels adrenal_right adrenal_left; do
  check "$thin is named as mostly thinner than 2 r0" \
    "sed -n \"s/.*warning: bag '$thin': [0-9]* of its [0-9]* voxels (\\([0-9.]*\\)%).*/\\1/p\" '$work/place.log' |
     awk '{v = \$1} END {exit !(v + 0 >= 50)}'"
done

check "the scan settles: the minimiser's steps, then the dynamics' ($(grep -o 'settled at step [0-9]*' "$work/place.log"))" \
  "grep -q \"^settled at step .*the FIRE minimiser's first\" '$work/place.log'"
check "every bag keeps at least 90% of its particles inside it" \
  "grep \"^  bag '\" '$work/place.log' | awk '{for (k = 1; k <= NF; ++k) if (\$k == \"inside\") {v = \$(k - 4); sub(/%/, \"\", v); n++; if (v + 0 < 90) bad = 1}} END {exit bad || n != 21}'"
# Each bag's median normal angle (the per-bag line's last figure): the median over every surface
# particle lies between the smallest and the largest of the bags' medians.
angles=$(sed -n "s/^  bag '.*median normal angle \([0-9.]*\) deg$/\1/p" "$work/place.log" | sort -g | sed -n '1p;$p' | tr '\n' ' ')
overall=$(sed -n 's/^shape fidelity: .*median normal angle \([0-9.]*\) deg$/\1/p' "$work/place.log")
check "the scan's median normal angle ($overall deg) lies within its bags' medians ($angles)" \
  "[ \$(grep -c \"^  bag '.*median normal angle [0-9.]* deg\$\" '$work/place.log') -eq 21 ] && \
   awk -v o='$overall' -v r='$angles' 'BEGIN {split(r, a, \" \"); exit !(o != \"\" && o + 0 >= a[1] + 0 && o + 0 <= a[2] + 0 && a[2] > a[1])}'"
exit $fail
