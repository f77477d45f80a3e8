#!/usr/bin/env bash
# `crusher gap-slice --fit-refill` as a user runs it on slices already run (gap_slice.csv in its documented format,
# src/tools/README.md): two pourings whose reloads at 500 rpm are 0.892 of those at 400 rpm, the refill law's ratio at
# a length of 5 mm for the shipped rock (chamber/refill_fit.hpp), give that length back; 300 and 600 rpm are predicted,
# not fitted, and refill_fit.csv says which; a missing folder and 400 rpm as a fitted speed are refused by name.
source "$(dirname "$0")/ros_env.bash"
crusher() { CRUSHER_NO_BUILD=1 bash "$src/scripts/crusher" "$@"; }
header="rpm,cycle,work_J_kg,closing_J_kg,peak_kN,peak_kPa,top_mm,sank_mm,bonds_broken,law_J_kg"
mkdir -p "$out/p1" "$out/p2"
printf '%s\n400,1,5,5,1,1,1,1,1,1\n400,2,2,2,1,1,1,1,1,1\n400,3,2,2,1,1,1,1,1,1\n500,1,5,5,1,1,1,1,1,1\n500,2,1.784,2,1,1,1,1,1,1\n600,2,0.5,2,1,1,1,1,1,1\n' "$header" >"$out/p1/gap_slice.csv"
printf '%s\n400,2,3,2,1,1,1,1,1,1\n500,2,2.676,2,1,1,1,1,1,1\n300,2,3.3,2,1,1,1,1,1,1\n' "$header" >"$out/p2/gap_slice.csv"
crusher gap-slice --fit-refill "$out/p1,$out/p2" --fit-rpm 500 --out "$out/fit" >"$out/fit.log" 2>&1 ||
  { cat "$out/fit.log"; echo "FAIL: the fit failed"; exit 1; }
d=$(sed -n 's/.*refill.length_mm \([0-9.]*\), rms.*/\1/p' "$out/fit.log")
/usr/bin/python3 -c "import sys; sys.exit(0 if abs($d - 5.0) < 0.1 else 1)" ||
  { cat "$out/fit.log"; echo "FAIL: fitted $d mm, made with 5 mm"; exit 1; }
[[ $(head -n 1 "$out/fit/refill_fit.csv") == "pouring,rpm,measured,law,fitted" ]] || { echo "FAIL: refill_fit.csv header"; exit 1; }
grep -q "^$out/p1,600,0.25,[0-9.]*,0$" "$out/fit/refill_fit.csv" || { cat "$out/fit/refill_fit.csv"; echo "FAIL: 600 rpm not listed as predicted"; exit 1; }
grep -q "^$out/p2,500,0.892,0.892[0-9]*,1$" "$out/fit/refill_fit.csv" || { cat "$out/fit/refill_fit.csv"; echo "FAIL: 500 rpm not listed as fitted"; exit 1; }
if crusher gap-slice --fit-refill "$out/none" --fit-rpm 500 --out "$out/x" >"$out/x.log" 2>&1; then echo "FAIL: a missing folder was accepted"; exit 1; fi
grep -q "none/gap_slice.csv not found" "$out/x.log" || { cat "$out/x.log"; echo "FAIL: the refusal does not name the file"; exit 1; }
if crusher gap-slice --fit-refill "$out/p1" --fit-rpm 400 --out "$out/x" >"$out/x.log" 2>&1; then echo "FAIL: 400 rpm fitted against itself"; exit 1; fi
grep -q "400 rpm is the reference" "$out/x.log" || { cat "$out/x.log"; echo "FAIL: the refusal does not say why"; exit 1; }
echo "gap slice refill fit: passed"
