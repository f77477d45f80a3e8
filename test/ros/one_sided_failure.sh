#!/usr/bin/env bash
# A bad key in one node's part of the config ends the run within 10 s with a non-zero status naming the real cause,
# instead of the other node waiting coupling.first_timeout_s (300 s here):
#  A, B: `crusher run` with a bad key in dem: or flow: is refused before any node starts (the wrapper reads the config
#        through the schema, crusher config --json), naming the key;
#  C: the nodes themselves (rosrun, no wrapper): dem_node refuses the dem: key and tells mbd_node on the coupling
#     topic, which stops naming it.
source "$(dirname "$0")/ros_env.bash"
export OMP_WAIT_POLICY=passive CRUSHER_NO_BUILD=1 CRUSHER_BUILD_ROOT=$out/buildroot
case_with() {  # SECTION KEY: quick_demo with SECTION.KEY added -> $out/KEY.yaml
  /usr/bin/python3 - "$src/launch_free_configs/quick_demo.yaml" "$out/$2.yaml" "$1" "$2" <<'PY'
import sys, yaml
c = yaml.safe_load(open(sys.argv[1]))
c.setdefault(sys.argv[3], {})[sys.argv[4]] = 1
yaml.safe_dump(c, open(sys.argv[2], "w"))
PY
}
stamped() { while IFS= read -r l; do printf '%s %s\n' "$EPOCHREALTIME" "$l"; done; }
run_fails() {  # NAME KEY: crusher run fails naming KEY within 10 s
  local s0 rc=0
  s0=$(date +%s)
  timeout 120 "$src/scripts/crusher" run "$out/$2.yaml" --out "$out/$1" >"$out/$1.log" 2>&1 || rc=$?
  [[ $rc != 0 ]] || { cat "$out/$1.log"; echo "FAIL: $1: no failure reported"; exit 1; }
  grep -q "$2" "$out/$1.log" || { cat "$out/$1.log"; echo "FAIL: $1: the cause ($2) is not named"; exit 1; }
  (($(date +%s) - s0 <= 10)) || { echo "FAIL: $1: the run took more than 10 s to end"; exit 1; }
  echo "$1: exit $rc in $(($(date +%s) - s0)) s naming $2"
}
case_with dem bogus_dem_key
run_fails A bogus_dem_key
case_with flow bogus_flow_key
run_fails B bogus_flow_key
# C: the nodes on a private master, as a user of rosrun starts them.
start_master
rosrun inertia_crusher dem_node _config:="$out/bogus_dem_key.yaml" _out:="$out/C" >"$out/C_dem.log" 2>&1 &
pids+=($!)
s0=$(date +%s)
rc=0
timeout 60 rosrun inertia_crusher mbd_node _config:="$out/bogus_dem_key.yaml" _out:="$out/C" >"$out/C_mbd.log" 2>&1 || rc=$?
waited=$(($(date +%s) - s0))
[[ $rc != 0 && $rc != 124 ]] || { tail -n 20 "$out/C_mbd.log" "$out/C_dem.log"; echo "FAIL: C: mbd_node exit $rc"; exit 1; }
grep -q "bogus_dem_key" "$out/C_mbd.log" || { tail -n 20 "$out/C_mbd.log"; echo "FAIL: C: mbd_node does not name dem_node's cause"; exit 1; }
echo "C: mbd_node exit $rc, $waited s after start, naming dem_node's refusal"
echo "one-sided failures end in seconds naming the cause: passed"
