#!/usr/bin/env bash
# A peer that never answers: each node stops on its own after the configured timeout with a clear error,
# exits non-zero, and leaves a bag that opens and reads. A DEM node that stops (here by SIGTERM mid-run)
# tells mbd_node, which stops at once, well before its timeout, naming the reason.
source "$(dirname "$0")/ros_env.bash"
/usr/bin/python3 - "$src/launch_free_configs/quick_demo.yaml" "$out/case.yaml" <<'PY'
import sys, yaml
c = yaml.safe_load(open(sys.argv[1]))
c["coupling"].update(timeout_s=2.0, first_timeout_s=3.0)
c["dem"]["feed"]["max_fed_kg"] = 1.0
yaml.safe_dump(c, open(sys.argv[2], "w"))
PY
start_master
check() {  # NAME LOG BAG EXPECTED-MESSAGE
  local rc=$1 log=$2 bag=$3 msg=$4
  [[ $rc != 0 ]] || { echo "FAIL: $(basename "$bag") writer exited 0 without its peer"; exit 1; }
  grep -q "$msg" "$log" || { cat "$log"; echo "FAIL: no clear error ('$msg')"; exit 1; }
  /usr/bin/python3 -c 'import rosbag, sys; b = rosbag.Bag(sys.argv[1]); print(sys.argv[1], b.get_message_count(), "messages")' "$bag" ||
    { echo "FAIL: $bag is not readable"; exit 1; }
}
rc=0
timeout 120 rosrun inertia_crusher mbd_node _config:="$out/case.yaml" _out:="$out/mbd" >"$out/mbd.log" 2>&1 || rc=$?
check $rc "$out/mbd.log" "$out/mbd/run.bag" "no answer from the DEM node"
[[ -f $out/mbd/summary.json ]] || { echo "FAIL: mbd_node kept no summary"; exit 1; }
rc=0
timeout 120 rosrun inertia_crusher dem_node _config:="$out/case.yaml" _out:="$out/dem" >"$out/dem.log" 2>&1 || rc=$?
check $rc "$out/dem.log" "$out/dem/dem.bag" "no geometry state from mbd_node"

# dem_node stopped mid-run: mbd_node must not wait for its timeout (here raised to 60 s to tell them apart, the
# first one too: on a loaded machine the first coupling step can take longer than 3 s).
sed -i 's/timeout_s: 2.0/timeout_s: 60.0/; s/first_timeout_s: 3.0/first_timeout_s: 60.0/' "$out/case.yaml"
rosrun inertia_crusher dem_node _config:="$out/case.yaml" _out:="$out/both" >"$out/dem2.log" 2>&1 &
dem_pid=$!
pids+=($dem_pid)
( r=0; timeout 120 rosrun inertia_crusher mbd_node _config:="$out/case.yaml" _out:="$out/both" >"$out/mbd2.log" 2>&1 || r=$?
  echo $r >"$out/mbd2.rc" ) &
mbd_pid=$!
timeout 60 rostopic echo -n 1 /crusher/geometry_wrench/step >/dev/null  # coupled steps under way
kill -TERM "$dem_pid" || { cat "$out/dem2.log"; echo "FAIL: dem_node had already exited"; exit 1; }
stopped_at=$(date +%s.%N)
wait "$mbd_pid"
took=$(/usr/bin/python3 -c "import time; print(f'{time.time() - $stopped_at:.1f}')")
echo "mbd_node stopped $took s after dem_node"
check "$(cat "$out/mbd2.rc")" "$out/mbd2.log" "$out/both/run.bag" "dem_node has stopped: stopped by a signal"
/usr/bin/python3 -c "import sys; sys.exit(0 if $took < 10 else 1)" || { echo "FAIL: mbd_node took $took s to stop"; exit 1; }
echo "peer timeouts and stops: passed"
