#!/usr/bin/env bash
# CTest wrapper: rostest of mbd_node (topics in sim time, complete bag), then the bad-config exit path.
set -euo pipefail
export PATH=/usr/bin:/bin:$PATH
setup=$CRUSHER_BUILD_DIR/../devel/setup.bash
[[ -f $setup ]] || setup=$CRUSHER_BUILD_DIR/devel/setup.bash
set +u; source "$setup"; set -u
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
export ROS_LOG_DIR=$out/log
rostest --text inertia_crusher mbd_node.test out:="$out/run"

# A bad config is rejected before any simulation, naming the key; the node exits non-zero.
cfg=$CRUSHER_SOURCE_DIR/launch_free_configs/gyp1200_400rpm.yaml
/usr/bin/python3 -c 'import sys, yaml; c = yaml.safe_load(open(sys.argv[1])); c["run"]["duration_s"] = -3
yaml.safe_dump(c, open(sys.argv[2], "w"))' "$cfg" "$out/bad.yaml"
port=$(/usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')
export ROS_MASTER_URI=http://127.0.0.1:$port
rosmaster --core -p "$port" >/dev/null 2>&1 &
master=$!
trap 'kill $master 2>/dev/null; rm -rf "$out"' EXIT
sleep 1.5
rc=0
msg=$(rosrun inertia_crusher mbd_node _config:="$out/bad.yaml" _out:="$out/bad" 2>&1) || rc=$?
echo "$msg"
[[ $rc == 2 ]] || { echo "FAIL: bad config exit status $rc, expected 2"; exit 1; }
grep -q "run.duration_s" <<<"$msg" || { echo "FAIL: message does not name run.duration_s"; exit 1; }
[[ ! -e $out/bad/run.bag ]] || { echo "FAIL: a bag was written for a rejected config"; exit 1; }
echo "bad-config check passed"
