#!/usr/bin/env bash
# No shell between a tool and its helper programs: an out dir whose name holds quotes, `;`, `$()` and spaces is
# a name (diagnose and piston_die write their plots into it), never a command (no bait file appears).
source "$(dirname "$0")/ros_env.bash"
cd "$out"
bin=$(dirname "$(catkin_find --first-only --libexec inertia_crusher diagnose)")
cfg=$src/launch_free_configs/gyp1200_400rpm_bed.yaml
"$bin/make_recording" --config "$cfg" --effect none --value 0 --seconds 5 --settle-s 1 --out rec.csv >/dev/null
name="d i';touch PWNED;'\$(touch PWNED2)\""
"$bin/diagnose" --recording rec.csv --config "$cfg" --settle-s 1 --model-seconds 1 --out "$name" >diag.log 2>&1 ||
  { tail -n 20 diag.log; echo "FAIL: diagnose exited non-zero"; exit 1; }
printf 's,p_MPa,phase\n0,0,load\n0.1,1,load\n0.2,4,load\n0.3,12,load\n0.28,6,unload\n0.26,1,unload\n' >lab.csv
"$bin/piston_die" --lab lab.csv --out "$name/pd" >pd.log 2>&1 || { tail -n 20 pd.log; echo "FAIL: piston_die exited non-zero"; exit 1; }
ls -la
[[ ! -e PWNED && ! -e PWNED2 ]] || { echo "FAIL: a file name was run as a shell command"; exit 1; }
grep -q "plotting failed\|not found" diag.log pd.log && { cat diag.log pd.log; echo "FAIL: a plot script failed"; exit 1; }
ls "$name"/*.png "$name"/pd/*.png >/dev/null || { echo "FAIL: no plots in '$name'"; exit 1; }
echo "no shell: hostile out dir names are names: passed"
