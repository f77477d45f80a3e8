#!/usr/bin/env bash
# Every subcommand of scripts/crusher answers --help with its usage (exit 0, the subcommand named), without
# building or installing anything; an unknown subcommand is refused naming the accepted ones; `run --duration`
# at or below the settle time is refused, and so is a run into an out dir that holds one (without --resume/--force);
# numeric flags out of range or not numbers are refused by name.
set -euo pipefail
crusher=$CRUSHER_SOURCE_DIR/scripts/crusher
for sub in demo test run validate bench mbd-bench flow-bench calibrate diagnose make-recording export config build setup env; do
  text=$(bash "$crusher" "$sub" --help) || { echo "FAIL: crusher $sub --help exited non-zero"; exit 1; }
  grep -q "^usage:" <<<"$text" || { echo "FAIL: crusher $sub --help printed no usage: $text"; exit 1; }
  grep -q "crusher .*$sub" <<<"$text" || { echo "FAIL: crusher $sub --help does not name $sub: $text"; exit 1; }
done
# Captured, not piped: under pipefail, grep -q's early exit can kill the writer with SIGPIPE (a flaky failure).
text=$(bash "$crusher" --help)
grep -q "crusher validate" <<<"$text" || { echo "FAIL: crusher --help lacks validate: $text"; exit 1; }
if msg=$(bash "$crusher" frobnicate 2>&1); then echo "FAIL: an unknown subcommand was accepted"; exit 1; fi
grep -q "accepted: demo" <<<"$msg" || { echo "FAIL: unknown subcommand message: $msg"; exit 1; }
# A run shorter than its settle time has no summary window: refused before building, naming both.
if msg=$(CRUSHER_NO_BUILD=1 bash "$crusher" run "$CRUSHER_SOURCE_DIR/launch_free_configs/gyp1200_400rpm.yaml" \
    --duration 3 --out "$(mktemp -d)" 2>&1); then echo "FAIL: --duration 3 below settle_s 4 was accepted"; exit 1; fi
grep -q "run.settle_s = 4" <<<"$msg" || { echo "FAIL: the duration guard does not name run.settle_s: $msg"; exit 1; }
# Numeric flags are checked, naming the flag, the value and the range (issue 22: `--duration -1|0|abc|nan` was
# ignored, 1e9 passed): crusher run (run.duration_s's range), the C++ tools (core::parse_number), crusher sweep.
for bad in -1 0 abc nan 1e9; do
  if msg=$(CRUSHER_NO_BUILD=1 bash "$crusher" run "$CRUSHER_SOURCE_DIR/launch_free_configs/gyp1200_400rpm.yaml" \
      --duration "$bad" --out "$(mktemp -d)" 2>&1); then echo "FAIL: run --duration $bad was accepted"; exit 1; fi
  grep -qF "run: --duration '$bad': accepted a number of seconds in [0.001,3600]" <<<"$msg" ||
    { echo "FAIL: run --duration $bad: $msg"; exit 1; }
done
for tool in "mbd-bench --seconds nan" "bench --steps 0" "flow-bench --seconds abc"; do
  read -r sub flag bad <<<"$tool"
  if msg=$(CRUSHER_NO_BUILD=1 bash "$crusher" $sub $flag $bad 2>&1); then echo "FAIL: $sub $flag $bad was accepted"; exit 1; fi
  grep -qE -- "$flag $bad: accepted a (whole )?number in \[" <<<"$msg" || { echo "FAIL: $sub $flag $bad: $msg"; exit 1; }
done
if msg=$(CRUSHER_NO_BUILD=1 bash "$crusher" sweep "$CRUSHER_SOURCE_DIR/launch_free_configs/gyp1200_400rpm.yaml" \
    --vary mbd.drive.speed_rpm=400 --out "$(mktemp -d)" --jobs 0 2>&1); then echo "FAIL: sweep --jobs 0 was accepted"; exit 1; fi
grep -q -- "--jobs: '0': accepted a whole number in \[1, 1024\]" <<<"$msg" || { echo "FAIL: sweep --jobs 0: $msg"; exit 1; }
# An out dir that holds a run is not replaced silently: refused without --resume or --force, its checkpoints kept.
held=$(mktemp -d)
mkdir -p "$held/checkpoint" && touch "$held/summary.json" "$held/checkpoint/mbd.0000000040.ckpt"
if msg=$(CRUSHER_NO_BUILD=1 bash "$crusher" run "$CRUSHER_SOURCE_DIR/launch_free_configs/quick_demo.yaml" --out "$held" 2>&1); then
  echo "FAIL: a run into an out dir holding a run was accepted"; exit 1; fi
grep -q "already holds a run.*--resume.*--force" <<<"$msg" || { echo "FAIL: the held out dir message: $msg"; exit 1; }
[[ -f $held/checkpoint/mbd.0000000040.ckpt ]] || { echo "FAIL: the earlier run's checkpoint was deleted"; exit 1; }
rm -rf "$held"
echo "every subcommand answers --help; a run shorter than its settle time, or into a run's out dir, is refused"
