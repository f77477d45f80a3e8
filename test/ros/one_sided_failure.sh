#!/usr/bin/env bash
# When one node of a coupled `crusher run` rejects its part of the config, the run ends within 10 s with a
# non-zero status naming the real cause, instead of the other node waiting coupling.first_timeout_s (300 s here):
#  A: a bad key in dem: (dem_node refuses it and tells mbd_node on the coupling topic);
#  B: a bad key in flow: (mbd_node refuses it; the wrapper stops dem_node).
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
run_fails() {  # NAME KEY NODE: crusher run fails naming KEY and NODE, and ends within 10 s of the first error
  local rc
  timeout 120 "$src/scripts/crusher" run "$out/$2.yaml" --out "$out/$1" 2>&1 | stamped >"$out/$1.log" || true
  rc=$(grep -o "(exit [0-9]*)" "$out/$1.log" | tr -dc 0-9)
  [[ -n $rc && $rc != 0 ]] || { cat "$out/$1.log"; echo "FAIL: $1: no failure reported"; exit 1; }
  grep -q "$2" "$out/$1.log" || { cat "$out/$1.log"; echo "FAIL: $1: the cause ($2) is not named"; exit 1; }
  grep -q "$3 exited with status" "$out/$1.log" || { cat "$out/$1.log"; echo "FAIL: $1: the failing node is not named"; exit 1; }
  /usr/bin/python3 - "$out/$1.log" "$2" "$1" "$rc" <<'PY'
import sys
lines = [l.split(" ", 1) for l in open(sys.argv[1]) if " " in l]
t_err = next(float(t) for t, l in lines if sys.argv[2] in l)
t_exit = float(lines[-1][0])
print(f"{sys.argv[3]}: exit {sys.argv[4]}, {t_exit - t_err:.1f} s after the first error naming {sys.argv[2]} "
      "(both nodes stopped, bags merged, summary printed)")
if t_exit - t_err > 10:
    sys.exit(f"FAIL: {sys.argv[3]}: the run took more than 10 s to end")
PY
}
case_with dem bogus_dem_key
run_fails A bogus_dem_key dem_node
case_with flow bogus_flow_key
run_fails B bogus_flow_key mbd_node
echo "one-sided failures end in seconds naming the cause: passed"
