#!/usr/bin/env bash
# Checkpoint and resume of a coupled run, through `scripts/crusher run` as a user runs it:
#   A: 0.12 s in one go, checkpoints every 0.04 s;
#   B: the same case stopped at 0.08 s, a bit flipped in dem_node's newest checkpoint, then `--resume --duration
#      0.12`: the damaged checkpoint is refused by name and the run resumes from the older one (0.04 s).
# check_resume.py requires B's joined run.bag to equal A's message for message, byte for byte (every topic of
# both nodes: wrenches, liner states, test point, power, product, particles), the same summary.json and break
# log, and every coupling step exactly once. C: the same after both nodes are killed (a crash).
# D: Ctrl-C (SIGINT to both nodes) mid-run: both checkpoint the same step (mbd_node lets the DEM finish the step
# it is on), the resume starts there, and the joined bag holds every step once. E: the same with dem_node stopped
# first (mbd_node stops while waiting for it).
source "$(dirname "$0")/ros_env.bash"
export OMP_WAIT_POLICY=passive CRUSHER_NO_BUILD=1 CRUSHER_BUILD_ROOT=$out/buildroot

/usr/bin/python3 - "$src/launch_free_configs/quick_demo.yaml" "$out/case.yaml" <<'PY'
import sys, yaml
c = yaml.safe_load(open(sys.argv[1]))
c["run"].update(duration_s=0.12, settle_s=0.0, tf_hz=100, checkpoint_every_s=0.04)
# Rock thrown in fast lands on the mantle's distribution cone and in the hopper by ~0.05 s: contacts with both
# liners and between rocks, and (bonds at a tenth of Table 4's strength) breakage, across the checkpoints.
c["dem"]["feed"].update(max_fed_kg=3.0, drop_speed_m_s=4.0)
c["dem"]["bpm"]["bond"].update(normal_strength_MPa=2.5, shear_strength_MPa=0.9)
yaml.safe_dump(c, open(sys.argv[2], "w"))
PY
crusher=$src/scripts/crusher
run_case A
run_case B --duration 0.08
ls "$out/B/checkpoint"
cp "$out/B/breaks.csv" "$out/B_first_leg_breaks.csv"
# One bit flipped in dem_node's newest checkpoint (0.08 s): refused by name, the older step (0.04 s) resumed.
flip_bit "$out/B/checkpoint/dem.0000000080.ckpt" 5000
run_case B --duration 0.12 --resume
grep -h "resumed\|checkpoint at\|damaged" "$out/B.log" | sed 's/\x1b\[[0-9;]*m//g' | head -n 8 || true  # display only (SIGPIPE under pipefail)
grep -q "dem.0000000080.ckpt: damaged" "$out/B.log" && grep -q "resumed from the checkpoint at step 40 " "$out/B.log" ||
  { echo "FAIL: the damaged newest checkpoint was not passed over for the older one"; exit 1; }
/usr/bin/python3 "$src/test/ros/check_resume.py" "$out/A" "$out/B"

# C: a crash. Both nodes are killed (SIGKILL: no bag closed, no final checkpoint) soon after the checkpoint at
# 0.04 s; `--resume` continues from it, and the result is again the uninterrupted run, byte for byte.
"$crusher" run "$out/case.yaml" --out "$out/C" >"$out/C.log" 2>&1 &
crashed=$!
for _ in $(seq 1 600); do
  [[ -f $out/C/checkpoint/mbd.0000000040.ckpt && -f $out/C/checkpoint/dem.0000000040.ckpt ]] && break
  sleep 0.05
done
pkill -9 -f "_out:=$out/C" || true
wait "$crashed" || true
[[ -f $out/C/checkpoint/dem.0000000040.ckpt ]] || { tail -n 20 "$out/C.log"; echo "FAIL: no checkpoint before the crash"; exit 1; }
ls "$out/C"
run_case C --resume
grep -h "resumed" "$out/C.log" | sed 's/\x1b\[[0-9;]*m//g'
/usr/bin/python3 "$src/test/ros/check_resume.py" "$out/A" "$out/C"

# D: SIGINT to both nodes. E: SIGINT to dem_node alone: mbd_node learns it has stopped while waiting for the
# step dem_node was asked for, and checkpoints that step, whose liner state it had already sent (it must be in the
# bag once: recorded when a step is answered, not when it is sent).
for leg in D E; do  # (not "case": run_case reads that name)
  pattern="_out:=$out/$leg"
  [[ $leg == E ]] && pattern="dem_node.*_out:=$out/$leg"
  "$crusher" run "$out/case.yaml" --out "$out/$leg" >"$out/$leg.log" 2>&1 &
  stopped=$!
  for _ in $(seq 1 600); do [[ -f $out/$leg/checkpoint/dem.0000000040.ckpt ]] && break; sleep 0.05; done
  sleep 0.5
  pkill -INT -f "$pattern" || true
  wait "$stopped" || true
  mbd_last=$(ls "$out/$leg/checkpoint" | grep '^mbd' | tail -n 1); dem_last=$(ls "$out/$leg/checkpoint" | grep '^dem' | tail -n 1)
  echo "$leg: after Ctrl-C: $mbd_last $dem_last"
  [[ ${mbd_last#mbd} == "${dem_last#dem}" && $mbd_last != mbd.0000000040.ckpt ]] ||
    { tail -n 20 "$out/$leg.log"; echo "FAIL: $leg: the nodes did not checkpoint the same step when stopped"; exit 1; }
  run_case "$leg" --resume
  /usr/bin/python3 - "$out/$leg/run.bag" "$leg" <<'PY'
import sys, rosbag
b = rosbag.Bag(sys.argv[1])
for topic in ("/crusher/geometry_state", "/crusher/geometry_wrench"):
    steps = [m.step for _, m, _ in b.read_messages([topic])]
    if steps != list(range(120)):
        sys.exit(f"FAIL: {sys.argv[2]}: {topic} steps are not 0..119 exactly once after Ctrl-C and resume ({len(steps)} messages)")
p = [m for _, m, _ in b.read_messages(["/crusher/product"])][-1]
bal = p.mass_in_chamber_kg + p.mass_discharged_kg + p.mass_lost_kg
if abs(bal - p.mass_fed_kg) > 0.005 * p.mass_fed_kg:
    sys.exit(f"FAIL: mass balance after the resume: fed {p.mass_fed_kg} kg, accounted {bal} kg")
print(f"{sys.argv[2]}: Ctrl-C and resume: 120 coupling steps once each, mass balance closes")
PY
done
