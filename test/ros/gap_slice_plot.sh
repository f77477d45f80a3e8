#!/usr/bin/env bash
# The gap slice's plot as `gap_slice` draws it (plot_gap_slice.py) on a run folder in its documented formats
# (src/tools/README.md): a panel per speed and the work per cycle; a folder without cycles is refused by name.
source "$(dirname "$0")/ros_env.bash"
d=$out/gs
mkdir -p "$d"
echo "rpm,cycle,work_J_kg,closing_J_kg,peak_kN,peak_kPa,top_mm,sank_mm,bonds_broken,law_J_kg" >"$d/gap_slice.csv"
echo "rpm,cycle,t_s,gap_mm,force_kN" >"$d/gap_slice_trace.csv"
if /usr/bin/python3 "$src/src/tools/plot_gap_slice.py" "$d" 2>"$d/err"; then
  echo "FAIL: a slice without cycles was plotted"; exit 1
fi
grep -q "holds no cycle" "$d/err" || { cat "$d/err"; echo "FAIL: the refusal does not say why"; exit 1; }
for rpm in 400 600; do
  for k in 1 2; do
    echo "$rpm,$k,$((3 - k)).5,$((3 - k)).6,2.1,100,175,-1,$((50 / k)),1.1" >>"$d/gap_slice.csv"
    for i in 0 1 2 3 4; do  # the plate closes 15 mm and opens again
      echo "$rpm,$k,0.0$k$i,$(( 120 - (i < 3 ? 5 * i : 5 * (4 - i)) )),0.$((i * (4 - i)))" >>"$d/gap_slice_trace.csv"
    done
  done
done
/usr/bin/python3 "$src/src/tools/plot_gap_slice.py" "$d" || { echo "FAIL: plot_gap_slice.py exited non-zero"; exit 1; }
[[ -s $d/gap_slice.png ]] || { ls "$d"; echo "FAIL: no gap_slice.png"; exit 1; }
echo "gap slice plot: passed"
