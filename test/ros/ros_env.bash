# Sourced by the test/ros/*.sh tests: the package's environment, a scratch folder removed on exit,
# background processes stopped on exit, and a private ROS master on a free port.
set -euo pipefail
export PATH=/usr/bin:/bin:$PATH
setup=$CRUSHER_BUILD_DIR/../devel/setup.bash
[[ -f $setup ]] || setup=$CRUSHER_BUILD_DIR/devel/setup.bash
set +u; source "$setup"; set -u
src=$CRUSHER_SOURCE_DIR
out=$(mktemp -d)
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; wait 2>/dev/null || true; rm -rf "$out"; }
trap cleanup EXIT
export ROS_LOG_DIR=$out/log

start_master() {  # private master with sim time on
  local port
  port=$(/usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')
  export ROS_MASTER_URI=http://127.0.0.1:$port ROS_HOSTNAME=127.0.0.1
  rosmaster --core -p "$port" >"$out/master.log" 2>&1 &
  pids+=($!)
  for _ in $(seq 1 100); do rosparam set /use_sim_time true 2>/dev/null && return 0; sleep 0.1; done
  echo "FAIL: the ROS master did not start"; exit 1
}

# `crusher run` of a test case as a user runs it: run_case NAME ARGS... runs CONFIG=$case (default $out/case.yaml)
# into $out/NAME, its log in $out/NAME.log; a failure prints the log's tail and fails the test.
run_case() {
  local name=$1; shift
  "$src/scripts/crusher" run "${case:-$out/case.yaml}" --out "$out/$name" "$@" >"$out/$name.log" 2>&1 ||
    { tail -n 30 "$out/$name.log"; echo "FAIL: crusher run $* failed"; exit 1; }
}

# flip_bit FILE BYTE: one bit of FILE changed in place (a damaged checkpoint).
flip_bit() {
  /usr/bin/python3 -c 'import sys; f = open(sys.argv[1], "r+b"); f.seek(int(sys.argv[2])); b = f.read(1); f.seek(int(sys.argv[2])); f.write(bytes([b[0] ^ 4]))' "$1" "$2"
}
