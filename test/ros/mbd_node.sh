#!/usr/bin/env bash
# CTest wrapper: rostest of mbd_node (topics in sim time, complete bag), then the bad-config exit path.
source "$(dirname "$0")/ros_env.bash"
rostest --text inertia_crusher mbd_node.test out:="$out/run"

# A bad config is rejected before any simulation, naming the key; the node exits non-zero.
/usr/bin/python3 -c 'import sys, yaml; c = yaml.safe_load(open(sys.argv[1])); c["run"]["duration_s"] = -3
yaml.safe_dump(c, open(sys.argv[2], "w"))' "$src/launch_free_configs/gyp1200_400rpm.yaml" "$out/bad.yaml"
start_master
rc=0
msg=$(rosrun inertia_crusher mbd_node _config:="$out/bad.yaml" _out:="$out/bad" 2>&1) || rc=$?
echo "$msg"
[[ $rc == 2 ]] || { echo "FAIL: bad config exit status $rc, expected 2"; exit 1; }
grep -q "run.duration_s" <<<"$msg" || { echo "FAIL: message does not name run.duration_s"; exit 1; }
[[ ! -e $out/bad/run.bag ]] || { echo "FAIL: a bag was written for a rejected config"; exit 1; }
echo "bad-config check passed"
