#!/usr/bin/env bash
# bop-lv-phantom from the command line: --help, a 4D file and a numbered series with their
# ground truth (the ejection fraction it prints against the CSV's volumes), and clear errors
# with a non-zero exit for bad volumes and a bad file name.
# Usage: bop_lv_phantom_cli.sh PATH/TO/bop-lv-phantom
set -u
exe=$1
source "$(dirname "$0")/cli-checks.sh"

bounded 30 "$work/help.txt" "$exe" --help
check "--help exits 0 and names the volumes" "grep -q -- '--edv-ml' '$work/help.txt'"

bounded 120 "$work/run.txt" "$exe" "$work/a/lv.nii.gz" --frames 6 --voxel-mm 2.5
rc=$?
cat "$work/run.txt"
check "a 4D file exits 0" "[ $rc -eq 0 ] && [ -s '$work/a/lv.nii.gz' ] && [ -s '$work/a/lv-truth.csv' ]"
check "the truth CSV has a row per frame" "[ \$(wc -l <'$work/a/lv-truth.csv') -eq 7 ]"
# The printed exact EF is (max - min) / max of the CSV's exact volumes.
ef=$(awk -F, 'NR > 1 {if (max == "" || $3 > max) max = $3; if (min == "" || $3 < min) min = $3} END {printf "%.2f", 100 * (max - min) / max}' "$work/a/lv-truth.csv")
check "the printed ejection fraction ($ef%) is the CSV's" "grep -q \"ejection fraction: $ef% exact\" '$work/run.txt'"

bounded 120 "$work/series.txt" "$exe" "$work/b/frame.nii" --series
check "--series writes 8 numbered files" "[ -s '$work/b/frame-00.nii' ] && [ -s '$work/b/frame-07.nii' ] && [ ! -e '$work/b/frame-08.nii' ]"

bounded 30 "$work/e1.txt" "$exe" "$work/c/lv.nii" --edv-ml 50 --esv-ml 80
rc=$?
check "end-systolic above end-diastolic exits non-zero naming --esv-ml" "[ $rc -ne 0 ] && grep -q -- '--esv-ml' '$work/e1.txt'"
bounded 30 "$work/e2.txt" "$exe" "$work/c/lv.png"
rc=$?
check "a file that is not .nii or .nii.gz exits non-zero saying so" "[ $rc -ne 0 ] && grep -q 'expected a .nii or .nii.gz' '$work/e2.txt'"
exit $fail
