#!/usr/bin/env bash
# Integration test of the coupled run: mbd_node and dem_node started by rosrun on a private master,
# lockstep over ROS topics (dem_node first, then mbd_node: either may start first), then
#  1. dem.bag is merged into run.bag (merge_bags, as scripts/crusher run does) and check_coupled_run.py asserts
#     on it (every topic of both nodes, no step missing or duplicated, wrenches, mass balance, PSD);
#  2. rviz with rviz/crusher.rviz under Xvfb, fed by the merged run.bag, is screenshot; check_screenshot.py
#     finds the liners' pixels in the 3D view and requires particle-coloured pixels within the chamber they
#     outline, centred on it, in several fragment colours.
source "$(dirname "$0")/ros_env.bash"
export OMP_WAIT_POLICY=passive

# A short case of the quick demo: 0.6 s, a small charge (6 kg, all pre-filled).
/usr/bin/python3 - "$src/launch_free_configs/quick_demo.yaml" "$out/case.yaml" <<'PY'
import sys, yaml
c = yaml.safe_load(open(sys.argv[1]))
c["run"].update(duration_s=0.6, settle_s=0.3, tf_hz=20)
c["dem"]["feed"].update(max_fed_kg=6.0, drop_speed_m_s=3.0)
yaml.safe_dump(c, open(sys.argv[2], "w"))
PY
start_master
rosrun inertia_crusher dem_node _config:="$out/case.yaml" _out:="$out/run" >"$out/dem.log" 2>&1 &
dem_pid=$!
pids+=($dem_pid)
sleep 1
start=$(date +%s.%N)
rosrun inertia_crusher mbd_node _config:="$out/case.yaml" _out:="$out/run" >"$out/mbd.log" 2>&1 ||
  { tail -n 20 "$out/mbd.log" "$out/dem.log"; echo "FAIL: mbd_node failed"; exit 1; }
wait "$dem_pid" || { tail -n 20 "$out/dem.log"; echo "FAIL: dem_node failed"; exit 1; }
wall=$(/usr/bin/python3 -c "import time; print(f'{time.time() - $start:.1f}')")
grep -h "simulated" "$out/mbd.log" "$out/dem.log" | sed 's/\x1b\[[0-9;]*m//g'
# Before the run: a wall-time estimate in h/min/s (issue 21), not a bare count of seconds.
grep -qE "dem_node: estimate [0-9]+ (d|h|min|s)( [0-9]+ (h|min|s))? of wall time" "$out/dem.log" ||
  { grep -h "estimate" "$out/dem.log"; echo "FAIL: dem_node printed no wall-time estimate before the run"; exit 1; }
echo "coupled case wall time: $wall s"
# One bag, as scripts/crusher run makes it: dem.bag merged into run.bag (mbd.bag: mbd_node's own, for the check).
cp "$out/run/run.bag" "$out/run/mbd.bag"
rosrun inertia_crusher merge_bags "$out/run/run.bag" "$out/run/dem.bag" ||
  { echo "FAIL: merge_bags failed"; exit 1; }
/usr/bin/python3 "$src/test/ros/check_coupled_run.py" "$out/run"
# The run's plots as `crusher run` makes them, from the merged bag: the particle paths of trajectories.csv (Figure 20),
# the force map and its history (Figure 21).
/usr/bin/python3 "$src/src/tools/plot_run.py" --bag "$out/run/run.bag" --summary "$out/run/summary.json" \
  --out "$out/run" || { echo "FAIL: plot_run.py failed on the coupled run"; exit 1; }
for png in displacement power concave_forces force_history particle_paths mantle_path; do
  [[ -s $out/run/$png.png ]] || { echo "FAIL: plot_run.py wrote no $png.png for the coupled run"; exit 1; }
done
# scripts/run_windows.py reads the same bag its own way: its last window (the 2 drive cycles after the 0.3 s
# settle) must give summary.json's amplitude and power, and over both windows (the whole 0.6 s) the power into the
# rock must be what mbd_node's energy audit booked as its load (from the wrenches it applied, step by step).
/usr/bin/python3 "$src/scripts/run_windows.py" "$out/run/run.bag" --cycles 2 | tee "$out/windows.txt"
/usr/bin/python3 - "$out/windows.txt" "$out/run/summary.json" "$out/mbd.log" <<'PY' || exit 1
import json, re, sys
lines = open(sys.argv[1]).read().splitlines()
rows = [l.split() for l in lines if l.strip() and l.split()[0].replace(".", "").isdigit()]
# run_windows.py adds a "fines kg" column before "rock kW" when the run holds crushed fines (dem.fines: flow).
off = 1 if any("fines kg" in l for l in lines) else 0
s = json.load(open(sys.argv[2]))
amp, power = float(rows[-1][2]), float(rows[-1][3])
a_ref, p_ref = s["amplitude_x_mm"]["mean"], s["power_kW"]["mean"]
print(f"run_windows last window: amplitude {amp} mm, power {power} kW; summary.json: {a_ref:.2f} mm, {p_ref:.2f} kW")
if len(rows) != 2 or abs(amp - a_ref) > 0.01 * a_ref or abs(power - p_ref) > 0.05 * abs(p_ref) + 0.2:
    sys.exit("FAIL: run_windows.py disagrees with summary.json (or not 2 windows of 2 cycles in 0.6 s)")
audit = re.search(r"power, t = 0\.000-0\.60\d s: drive ([-\d.]+) kW = load ([-\d.]+) \+ absorbers ([-\d.]+)",
                  open(sys.argv[3]).read())
if not audit:
    sys.exit("FAIL: mbd_node did not log its power partition over the run")
drive, load, absorbers = map(float, audit.groups())
rock = sum(float(r[7 + off]) for r in rows) / len(rows)
print(f"power into the rock: {rock:.2f} kW from the bag's wrenches and twists, {load:.2f} kW in mbd_node's audit "
      f"(drive {drive:.2f} kW, absorbers {absorbers:.2f} kW)")
if not load > 0.5 or abs(rock - load) > 0.05 * load + 0.1:
    sys.exit("FAIL: the rock's power from the bag disagrees with mbd_node's energy audit (or the rock takes none)")
# The mantle's nutation: this lightly loaded chamber lets the vibrator swing the mantle nearly onto the concave
# (1.67 deg at rest against it, mbd_bench --load none --diag); not in radians, not another axis.
nut = [float(r[9 + off]) for r in rows]
print(f"mantle nutation per window: {nut} deg")
if not all(1.2 < n < 1.8 for n in nut):
    sys.exit("FAIL: run_windows.py's nutation is outside 1.2-1.8 deg for a lightly loaded quick demo")
PY
# A file that is not a bag: one line naming it, non-zero exit.
msg=$(/usr/bin/python3 "$src/scripts/run_windows.py" "$out/case.yaml" 2>&1) && { echo "FAIL: run_windows.py read a YAML file as a bag"; exit 1; }
[[ $msg == "run_windows: $out/case.yaml cannot be read as a bag"* ]] || { echo "FAIL: run_windows.py on a non-bag said: $msg"; exit 1; }

# What a user sees: rviz fed by the recorded DEM bag, under Xvfb.
export DISPLAY=:$((90 + RANDOM % 100)) LIBGL_ALWAYS_SOFTWARE=1
Xvfb "$DISPLAY" -screen 0 1024x720x24 >"$out/xvfb.log" 2>&1 &
pids+=($!)
sleep 2
rosparam set /use_sim_time false
rviz -d "$src/rviz/crusher.rviz" >"$out/rviz.log" 2>&1 &
pids+=($!)
sleep 8
# Looped over the first 0.2 s: the charge is pre-filled, and by the end most of it has been crushed and discharged.
rosbag play -q -l -u 0.2 "$out/run/run.bag" --topics /crusher/particles /crusher/liners /crusher/concave_force_markers \
  >"$out/play.log" 2>&1 &
pids+=($!)
sleep 10
/usr/bin/python3 "$src/test/ros/check_screenshot.py" "$DISPLAY" "$out/screenshot.png" || { [[ -n ${CRUSHER_KEEP_SCREENSHOT:-} ]] && cp "$out/screenshot.png" "$CRUSHER_KEEP_SCREENSHOT"; exit 1; }
if [[ -n ${CRUSHER_KEEP_SCREENSHOT:-} ]]; then cp "$out/screenshot.png" "$CRUSHER_KEEP_SCREENSHOT"; fi
