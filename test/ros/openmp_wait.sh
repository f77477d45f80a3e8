#!/usr/bin/env bash
# OpenMP threads sleep while they wait (a shared machine, issue 22) unless the user chose: dem_node started by hand
# without OMP_WAIT_POLICY runs with it passive (it re-executes itself with it set: libgomp reads it only when it
# loads), says so in its log, and keeps the user's own choice. Checked in the process's environment
# (/proc/PID/environ), which is what libgomp read. Before: no policy was set; the DEM's threads spun.
source "$(dirname "$0")/ros_env.bash"
start_master
/usr/bin/python3 - "$src/launch_free_configs/quick_demo.yaml" "$out/case.yaml" <<'PY'
import sys, yaml
c = yaml.safe_load(open(sys.argv[1]))
c["dem"]["feed"].update(max_fed_kg=2.0)
yaml.safe_dump(c, open(sys.argv[2], "w"))
PY
check() {  # NAME EXPECTED-ENV EXPECTED-LOG [ENV...]: dem_node started with that environment
  local name=$1 want_env=$2 want_log=$3 pid
  shift 3
  env "$@" rosrun inertia_crusher dem_node _config:="$out/case.yaml" __name:="dem_$name" >"$out/$name.log" 2>&1 &
  pid=$!
  pids+=($pid)
  for _ in $(seq 1 600); do grep -q "OpenMP threads wait" "$out/$name.log" && break; sleep 0.1; done
  local env_now
  env_now=$(tr '\0' '\n' <"/proc/$pid/environ" | grep "^OMP_WAIT_POLICY=" || true)
  local line
  line=$(grep -o "OpenMP threads wait .*" "$out/$name.log" || true)
  kill -TERM "$pid" 2>/dev/null || true
  wait "$pid" 2>/dev/null || true
  line=$(sed 's/\x1b\[[0-9;]*m//g' <<<"$line")
  echo "$name: environ '$env_now', log '$line'"
  [[ $env_now == "$want_env" ]] || { tail -n 5 "$out/$name.log"; echo "FAIL: $name: environ '$env_now', expected '$want_env'"; exit 1; }
  [[ $line == *"$want_log"* ]] || { tail -n 5 "$out/$name.log"; echo "FAIL: $name: log '$line', expected '$want_log'"; exit 1; }
}
check default "OMP_WAIT_POLICY=passive" "wait passive (the default" -u OMP_WAIT_POLICY -u CRUSHER_OMP_WAIT_DEFAULT
check user "OMP_WAIT_POLICY=active" "wait active (OMP_WAIT_POLICY)" -u CRUSHER_OMP_WAIT_DEFAULT OMP_WAIT_POLICY=active
echo "OpenMP wait policy: passive by default, the user's choice kept"
