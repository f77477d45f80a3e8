#!/usr/bin/env bash
# A write error (a full disk, a file size limit) ends a run with an error naming the file, exit 1 and no abort, and
# `crusher run` says what the folder really holds (issue 22). No root needed: a file size limit (RLIMIT_FSIZE; the
# nodes ignore SIGXFSZ, so a write past it fails with EFBIG) stands in for a full disk.
#  A: a fast run (run.load flow, checkpoints every 0.5 s); after its first checkpoint mbd_node's limit is lowered to
#     64 KB (prlimit): mbd_node names the file it could not write (a bag segment or the next checkpoint, whichever
#     meets the limit first) and exits 1, summary.json is valid JSON saying why it stopped, the checkpoint before
#     the error is kept, the wrapper says what was kept (no run.bag after a segment's error), and `--resume` (no
#     limit) runs to the end.
#  B: a bed run (one run.bag) under `ulimit -f 256` (KB) whose summary.json cannot be written either (its temporary
#     file's name is taken by a folder): the node says there is no summary, the wrapper that neither summary.json
#     nor a readable run.bag was kept.
# Before: the node aborted on rosbag::BagIOException (exit 134), summary.json was lost, and the wrapper said the bag
# and the summary were kept.
source "$(dirname "$0")/ros_env.bash"
export CRUSHER_NO_BUILD=1 CRUSHER_BUILD_ROOT=$out/buildroot CRUSHER_RUN_PLOTS=0
/usr/bin/python3 - "$src/launch_free_configs/gyp1200_400rpm.yaml" "$out/case.yaml" <<'PY'
import sys, yaml
c = yaml.safe_load(open(sys.argv[1]))
c["run"].update(duration_s=20.0, settle_s=0.5, checkpoint_every_s=0.5)  # long: the limit comes mid-run
yaml.safe_dump(c, open(sys.argv[2], "w"))
PY
fail() { tail -n 25 "$out/$1.log"; echo "FAIL: $1: $2"; exit 1; }
no_abort() {  # NAME: no abort, no uncaught exception
  ! grep -qiE "terminate called|core dumped|Aborted|BagIOException' *$" "$out/$1.log" || fail "$1" "a node aborted"
}

# A
"$src/scripts/crusher" run "$out/case.yaml" --out "$out/A" >"$out/A.log" 2>&1 &
run=$!
pids+=($run)
for _ in $(seq 1 1200); do [[ -f $out/A/checkpoint/mbd.0000000500.ckpt ]] && break; sleep 0.02; done
[[ -f $out/A/checkpoint/mbd.0000000500.ckpt ]] || fail A "no first checkpoint"
prlimit --pid "$(pgrep -f "inertia_crusher/mbd_node .*_out:=$out/A" | head -n 1)" --fsize=65536
rc=0
wait "$run" || rc=$?
no_abort A
echo "A: exit $rc; $(grep -o 'writing [^ ]* failed[^;]*' "$out/A.log" | head -n 1)"
[[ $rc == 1 ]] || fail A "exit $rc, expected 1"
# Which file meets the limit first is a race (the bag segment's next chunk or the checkpoint at step 1000); both are
# write errors, and each has its own truthful account of what was kept.
kept=$(grep -o "kept in .*" "$out/A.log" | tail -n 1)
echo "A: $kept"
if grep -q "writing $out/A/run.seg[0-9]*.bag failed: .*File too large" "$out/A.log"; then
  [[ $kept == *"summary.json ("*"checkpoint at step "*"not kept: run.bag"* ]] ||
    fail A "the wrapper's account of what was kept after a bag error: '$kept'"
elif grep -q "writing $out/A/checkpoint/mbd.0000001000.ckpt failed: .*File too large" "$out/A.log"; then
  [[ $kept == *"summary.json ("*"run.bag ("*"checkpoint at step 500 "* ]] ||
    fail A "the wrapper's account of what was kept after a checkpoint error: '$kept'"
  [[ ! -e $out/A/checkpoint/mbd.0000001000.ckpt ]] || fail A "the half-written checkpoint was left in place"
else
  fail A "neither the bag segment nor the checkpoint is named with the error"
fi
/usr/bin/python3 - "$out/A/summary.json" <<'PY' || fail A "summary.json"
import json, sys
s = json.load(open(sys.argv[1]))
assert "writing" in (s["stopped"] or "") and s["simulated_s"] > 0.5, s["stopped"]
PY
run_case A --resume
grep -q '"stopped": null' "$out/A/summary.json" || fail A "the resumed run did not reach its end"
/usr/bin/python3 -c 'import rosbag, sys; b = rosbag.Bag(sys.argv[1]); assert b.get_end_time() > 19.9, b.get_end_time()' "$out/A/run.bag" ||
  fail A "the resumed run's run.bag does not reach 20 s"

# B (2 s simulated)
mkdir -p "$out/B/summary.json.tmp"
rc=0
( ulimit -f 256; "$src/scripts/crusher" run "$out/case.yaml" --load bed --duration 2 --out "$out/B" >"$out/B.log" 2>&1 ) || rc=$?
no_abort B
echo "B: exit $rc; $(grep -o 'writing [^ ]* failed[^;]*' "$out/B.log" | head -n 1)"
[[ $rc == 1 ]] || fail B "exit $rc, expected 1"
grep -q "writing $out/B/run.bag failed: .*File too large" "$out/B.log" || fail B "run.bag is not named with the error"
grep -q "summary.json.tmp.*there is no summary of this run" "$out/B.log" || fail B "the node does not say it wrote no summary"
kept=$(grep -o "kept in .*" "$out/B.log" | tail -n 1)
echo "B: $kept"
[[ $kept == *"not kept: summary.json"*"a readable run.bag"* ]] || fail B "the wrapper's account of what was kept: '$kept'"
echo "write errors: named, exit 1, no abort, summary.json kept where it could be written, the wrapper truthful"
