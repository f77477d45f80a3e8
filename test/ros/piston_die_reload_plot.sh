#!/usr/bin/env bash
# The piston die's plots as `piston_die` draws them (plot_piston_die.py) on a run folder in its documented formats
# (src/tools/README.md): without reloads no reload plot; with --reloads files (a first pressing and a reload pushed
# 20 mm down the die and swept) piston_die_reloads.png, one panel per bed.
source "$(dirname "$0")/ros_env.bash"
d=$out/pd
plot() {
  /usr/bin/python3 "$src/src/tools/plot_piston_die.py" "$d" ||
    { echo "FAIL: plot_piston_die.py exited non-zero"; exit 1; }
}
mkdir -p "$d"
printf 'flow_material:\n  pressure: {modulus_MPa: 30, exponent: 2.5, rebound: 0.1}\n' >"$d/flow_material.yaml"
printf 's_max,phase,s,p_MPa\n0.3,load,0,0\n0.3,load,0.1,0.095\n0.3,load,0.2,0.537\n0.3,load,0.3,1.479\n' \
  >"$d/piston_die.csv"  # p = 30 MPa s^2.5 on loading
printf '0.3,unload,0.29,0.2\n0.3,unload,0.28,0\n' >>"$d/piston_die.csv"
plot
[[ -f $d/piston_die.png && ! -e $d/piston_die_reloads.png ]] ||
  { ls "$d"; echo "FAIL: expected piston_die.png and no reload plot without reloads"; exit 1; }
{ printf 'pouring,seed,s_max,pressing,s_start,s_top,s_reached,peak_MPa,loop_J_kg,loading_J_kg,loop_ratio,'
  printf 'bonds_broken,fragments,shift_mm,push_MPa,sweep_J_kg,passing_1mm\n'
  echo "0,1,0.3,0,0,0,0.3,0.68,23.1,28.6,1,475,300,0,0,6.3,0"
  echo "0,1,0.3,1,0.248,0.264,0.3,0.1,0.34,0.66,0.015,5,303,20,0.05,0.5,0"; } >"$d/piston_die_reloads.csv"
{ echo "pouring,seed,s_max,pressing,phase,s,p_MPa"
  for k in 0 1; do
    for s in 0.25 0.27 0.3; do echo "0,1,0.3,$k,load,$s,0.$((2 - k))"; done
    echo "0,1,0.3,$k,unload,0.29,0"
  done; } >"$d/piston_die_reload_curves.csv"
plot
[[ -s $d/piston_die_reloads.png ]] || { ls "$d"; echo "FAIL: no piston_die_reloads.png"; exit 1; }
echo "piston die reload plot: passed"
