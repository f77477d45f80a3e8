#!/usr/bin/env bash
# Loopback only: during a coupled `crusher run`, every listening socket of the run's processes (the master,
# mbd_node, dem_node: XML-RPC and TCPROS) is on 127.0.0.1 or ::1, and nothing answers on the machine's other
# addresses (before: both nodes listened on every interface, and an XML-RPC `shutdown` from outside stopped a run).
source "$(dirname "$0")/ros_env.bash"
export OMP_WAIT_POLICY=passive CRUSHER_NO_BUILD=1 CRUSHER_BUILD_ROOT=$out/buildroot
unset ROS_IP ROS_HOSTNAME
/usr/bin/python3 - "$src/launch_free_configs/quick_demo.yaml" "$out/case.yaml" <<'PY'
import sys, yaml
c = yaml.safe_load(open(sys.argv[1]))
c["run"].update(duration_s=0.4, settle_s=0.2, tf_hz=20)
c["dem"]["feed"].update(max_fed_kg=2.0)
yaml.safe_dump(c, open(sys.argv[2], "w"))
PY
"$src/scripts/crusher" run "$out/case.yaml" --out "$out/run" >"$out/run.log" 2>&1 &
pids+=($!)
run_pid=$!
seen=""
while kill -0 "$run_pid" 2>/dev/null; do
  ss -ltnpH 2>/dev/null | grep -E '"(mbd_node|dem_node|rosmaster)"' >>"$out/listen.txt" || true
  seen=$({ grep -oE '"(mbd_node|dem_node|rosmaster)"' "$out/listen.txt" || true; } | sort -u | tr -d '"' | tr '\n' ' ')
  [[ $seen == "dem_node mbd_node rosmaster " ]] && break
  sleep 0.2
done
sort -u "$out/listen.txt" | awk '{print $4, $6}'
[[ $seen == "dem_node mbd_node rosmaster " ]] || { tail -n 20 "$out/run.log"; echo "FAIL: listeners seen only for: $seen"; exit 1; }
if awk '{print $4}' "$out/listen.txt" | grep -vE '^(127\.[0-9.]+|\[::1\]|\[::ffff:127\.[0-9.]+\]):[0-9]+$'; then
  echo "FAIL: the run's processes listen on non-loopback addresses (above)"; exit 1
fi
# The nodes' ports, tried on every other address of this machine: nothing may answer.
for addr in $(hostname -I 2>/dev/null); do
  for port in $(awk '{print $4}' "$out/listen.txt" | sed 's/.*://' | sort -u); do
    if timeout 2 bash -c 'exec 3<>"/dev/tcp/$1/$2"' _ "$addr" "$port" 2>/dev/null; then
      echo "FAIL: port $port answers on $addr"; exit 1
    fi
  done
done
wait "$run_pid" || { tail -n 20 "$out/run.log"; echo "FAIL: the run failed"; exit 1; }
echo "loopback only: every listener of the run on 127.0.0.1 / ::1: passed"
