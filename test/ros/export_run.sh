#!/usr/bin/env bash
# `crusher export` as a user runs it, checked against the bags by check_export.py:
#  (a) a 2 s fast run (the shipped 400 rpm config): CSV rows equal the messages in plant units, one row per message;
#      the ';' / decimal-comma export parses back to the same numbers; its force map is exported, and a topic missing
#      from a bag (the test point alone copied out of it) is named as skipped;
#  (b) a 0.2 s coupled run (the quick demo, small charge): ParaView files hold every particle of every
#      /crusher/particle_state sample with its fields, the liners' triangles, and .pvd files listing them all;
#      its CSV has the force map;
#  (c) a file that is not a bag: exit 2 naming it.
source "$(dirname "$0")/ros_env.bash"
export OMP_WAIT_POLICY=passive
crusher() { CRUSHER_NO_BUILD=1 bash "$src/scripts/crusher" "$@"; }
check="/usr/bin/python3 $src/test/ros/check_export.py"

/usr/bin/python3 - "$src/launch_free_configs" "$out" <<'PY'
import sys, yaml
src, out = sys.argv[1:]
c = yaml.safe_load(open(src + "/gyp1200_400rpm.yaml"))
c["run"].update(duration_s=2.0, settle_s=1.0)
yaml.safe_dump(c, open(out + "/flow.yaml", "w"))
c = yaml.safe_load(open(src + "/quick_demo.yaml"))
c["run"].update(duration_s=0.2, settle_s=0.1, tf_hz=20)
c["dem"]["feed"].update(max_fed_kg=6.0, drop_speed_m_s=3.0)
yaml.safe_dump(c, open(out + "/coupled.yaml", "w"))
PY

# (a) fast run, CSV
crusher run "$out/flow.yaml" --out "$out/flow" >"$out/flow.log" 2>&1 ||
  { tail -n 30 "$out/flow.log"; echo "FAIL: crusher run (flow) failed"; exit 1; }
crusher export "$out/flow/run.bag" --csv "$out/csv" | tee "$out/export.log" || { echo "FAIL: export --csv failed"; exit 1; }
[[ -f $out/csv/concave_forces.csv ]] || { echo "FAIL: no concave_forces.csv from a fast run"; exit 1; }
/usr/bin/python3 - "$out/flow/run.bag" "$out/partial.bag" <<'PY'
import sys, rosbag
with rosbag.Bag(sys.argv[1]) as a, rosbag.Bag(sys.argv[2], "w") as b:
    for topic, m, t in a.read_messages(topics=["/crusher/test_point"]):
        b.write(topic, m, t)
PY
crusher export "$out/partial.bag" --csv "$out/csv_partial" >"$out/export_partial.log" ||
  { echo "FAIL: export of a bag with the test point only failed"; exit 1; }
grep -q "/crusher/concave_forces not in the bag: concave_forces.csv skipped" "$out/export_partial.log" ||
  { cat "$out/export_partial.log"; echo "FAIL: the missing force map is not named as skipped"; exit 1; }
crusher export "$out/flow/run.bag" --csv "$out/csv_de" --delimiter ';' --decimal , >/dev/null ||
  { echo "FAIL: export --delimiter ';' --decimal , failed"; exit 1; }
$check csv "$out/flow/run.bag" "$out/csv" "$out/csv_de"

# (b) coupled run, VTK (and CSV with the force map)
start=$(date +%s)
crusher run "$out/coupled.yaml" --out "$out/dem" >"$out/dem.log" 2>&1 ||
  { tail -n 30 "$out/dem.log"; echo "FAIL: crusher run (coupled) failed"; exit 1; }
echo "coupled run: $(($(date +%s) - start)) s wall"
crusher export "$out/dem/run.bag" --vtk "$out/vtk" --csv "$out/csv_dem" || { echo "FAIL: export --vtk failed"; exit 1; }
$check vtk "$out/dem/run.bag" "$out/vtk"
$check csv "$out/dem/run.bag" "$out/csv_dem"
[[ -f $out/csv_dem/concave_forces.csv ]] || { echo "FAIL: no concave_forces.csv from a coupled run"; exit 1; }

# (c) not a bag; bad options
rc=0; msg=$(crusher export "$out/flow.yaml" --csv "$out/x" 2>&1) || rc=$?
[[ $rc == 2 && $msg == *"$out/flow.yaml cannot be read as a bag"* ]] ||
  { echo "FAIL: export of a YAML file: exit $rc, said: $msg"; exit 1; }
rc=0; msg=$(crusher export "$out/flow/run.bag" --csv "$out/x" --decimal , 2>&1) || rc=$?
[[ $rc == 2 && $msg == *"--delimiter ';'"* ]] || { echo "FAIL: --decimal , with delimiter ',': exit $rc, said: $msg"; exit 1; }
echo "export check passed"
