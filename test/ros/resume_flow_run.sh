#!/usr/bin/env bash
# Checkpoint and resume of a fast run (run.load flow), through `scripts/crusher run` as a user runs it: the shipped
# 400 rpm config, 5 s with a 1 s settle, checkpoints every 1 s (mechanism, flow model, the node's outputs).
#   A: in one go;
#   B: stopped at 2.5 s (--duration), a bit flipped in its newest checkpoint (2.5 s), then `--resume` to 5 s: the
#      damaged checkpoint is refused by name and the run resumes from the older one (2 s);
#   D: Ctrl-C (SIGINT) mid-run: mbd_node checkpoints the step it stopped at (exit 130), `--resume` continues there.
# check_resume.py --fast requires B's and D's joined run.bag to equal A's message for message, byte for byte (test
# point, drive, product, tf, liners, cells, force map) and the same summary.json (but wall_s).
source "$(dirname "$0")/ros_env.bash"
export CRUSHER_NO_BUILD=1 CRUSHER_BUILD_ROOT=$out/buildroot CRUSHER_RUN_PLOTS=0

/usr/bin/python3 - "$src/launch_free_configs/gyp1200_400rpm.yaml" "$out/case.yaml" <<'PY'
import sys, yaml
c = yaml.safe_load(open(sys.argv[1]))
c["run"].update(duration_s=5.0, settle_s=1.0, checkpoint_every_s=1.0)
yaml.safe_dump(c, open(sys.argv[2], "w"))
PY
run_case A
ls "$out/A/checkpoint"
run_case B --duration 2.5
ls "$out/B/checkpoint"
flip_bit "$out/B/checkpoint/mbd.0000002500.ckpt" 3000
run_case B --resume
grep -h "resumed\|damaged" "$out/B.log" | sed 's/\x1b\[[0-9;]*m//g' | head -n 4 || true  # display only (SIGPIPE under pipefail)
grep -q "mbd.0000002500.ckpt: damaged" "$out/B.log" && grep -q "resumed from the checkpoint at step 2000 " "$out/B.log" ||
  { tail -n 20 "$out/B.log"; echo "FAIL: the damaged newest checkpoint was not passed over for the older one"; exit 1; }
/usr/bin/python3 "$src/test/ros/check_resume.py" --fast "$out/A" "$out/B"

"$src/scripts/crusher" run "$out/case.yaml" --out "$out/D" >"$out/D.log" 2>&1 &
stopped=$!
for _ in $(seq 1 600); do [[ -f $out/D/checkpoint/mbd.0000001000.ckpt ]] && break; sleep 0.02; done
pkill -INT -f "_out:=$out/D" || true
rc=0
wait "$stopped" || rc=$?
last=$(ls "$out/D/checkpoint" | tail -n 1)
echo "after Ctrl-C: exit $rc, newest checkpoint $last"
[[ $rc == 130 && $last != mbd.0000001000.ckpt && $last != mbd.0000005000.ckpt ]] ||
  { tail -n 20 "$out/D.log"; echo "FAIL: the stopped run did not checkpoint the step it stopped at (exit 130)"; exit 1; }
run_case D --resume
/usr/bin/python3 "$src/test/ros/check_resume.py" --fast "$out/A" "$out/D"
echo "fast run resume check passed"
