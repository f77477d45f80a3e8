#!/usr/bin/env bash
# The diagnosis reads a bag recorded by mbd_node: a run of the base model itself must be diagnosed as
# `none` (nothing missing), and a run with a concealed effect (motor droop) must be named.
source "$(dirname "$0")/ros_env.bash"
start_master
base=$src/launch_free_configs/gyp1200_400rpm_bed.yaml  # the diagnosis models the bed load (analysis/mbd_model.hpp)
# The plant: the base model with the motor's speed drooping under load (the paper assumes a stable speed).
CRUSHER_NO_BUILD=1 /usr/bin/python3 - "$base" "$out/plant.yaml" "$src/scripts" <<'PY'
import sys, yaml
sys.path.insert(0, sys.argv[3])
import config_yaml  # the config with its base resolved
c = config_yaml.load(sys.argv[1])
c["mbd"]["effects"]["motor_droop"] = {"enabled": True, "droop_rad_s_per_kNm": 0.5}
yaml.safe_dump(c, open(sys.argv[2], "w"))
PY
diagnose_bag() {  # CONFIG NAME: record 7 s, keep t > 4 s (start-up left out), diagnose against the base
  rosrun inertia_crusher mbd_node _config:="$1" _out:="$out/$2" _duration:=7 >"$out/$2.log" 2>&1
  rosbag filter "$out/$2/run.bag" "$out/$2/steady.bag" "t.to_sec() > 4.0" >/dev/null
  rosrun inertia_crusher diagnose --recording "$out/$2/steady.bag" --config "$base" --setpoint-rpm 400 \
    --no-plots --out "$out/$2/diag" >"$out/$2/diag.log" 2>&1 || { tail -n 20 "$out/$2/diag.log"; exit 1; }
  /usr/bin/python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); print(d["effect"])' "$out/$2/diag/diagnosis.json"
}
e=$(diagnose_bag "$base" base)
echo "base model bag diagnosed as: $e"
[[ $e == none ]] || { echo "FAIL: a run of the base model itself was diagnosed as '$e'"; exit 1; }
e=$(diagnose_bag "$out/plant.yaml" plant)
echo "plant bag (motor droop concealed) diagnosed as: $e"
[[ $e == motor_droop ]] || { echo "FAIL: expected motor_droop, got '$e'"; exit 1; }
echo "diagnosis from bags: passed"
