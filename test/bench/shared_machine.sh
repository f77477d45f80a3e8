#!/usr/bin/env bash
# Benchmark (not a test), issue 22 "shared machines": the quick demo's coupled run (shortened) alone, then two at
# once, wall times side by side and the ratio (each of the two at once / alone; the target on 2 cores is about 2).
# Usage: test/bench/shared_machine.sh [--policy passive|active] [--duration S] [--out DIR]
#   --policy: OMP_WAIT_POLICY for the runs (default: not set, so the programs' own default, passive, applies;
#             `active` is the spinning the issue measured: two runs at once took 20x longer each).
# Needs a built workspace (scripts/crusher build). Prints one line per run and a summary line.
set -euo pipefail
repo=$(cd "$(dirname "$0")/../.." && pwd)
policy="" duration=0.1 out=""
while (($#)); do
  case $1 in
    --policy) policy=$2; shift 2 ;;
    --duration) duration=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    *) echo "usage: $0 [--policy passive|active] [--duration S] [--out DIR]" >&2; exit 2 ;;
  esac
done
out=${out:-$(mktemp -d)}
mkdir -p "$out"
set +u
source "$("$repo/scripts/crusher" env)"
set -u
export CRUSHER_NO_BUILD=1 CRUSHER_RUN_PLOTS=0 CRUSHER_BUILD_ROOT=$out/buildroot
if [[ -n $policy ]]; then export OMP_WAIT_POLICY=$policy; else unset OMP_WAIT_POLICY; fi
unset CRUSHER_OMP_WAIT_DEFAULT
/usr/bin/python3 - "$repo/launch_free_configs/quick_demo.yaml" "$out/case.yaml" "$duration" <<'PY'
import sys, yaml
c = yaml.safe_load(open(sys.argv[1]))
d = float(sys.argv[3])
c["run"].update(duration_s=d, settle_s=d / 2)
yaml.safe_dump(c, open(sys.argv[2], "w"))
PY
one() {  # NAME: a run into $out/NAME; prints its wall time in s
  local t0 t1
  t0=$(date +%s.%N)
  "$repo/scripts/crusher" run "$out/case.yaml" --out "$out/$1" --force >"$out/$1.log" 2>&1 ||
    { tail -n 20 "$out/$1.log" >&2; echo "run $1 failed" >&2; exit 1; }
  t1=$(date +%s.%N)
  /usr/bin/python3 -c "print('%.1f' % ($t1 - $t0))"
}
load0=$(cut -d" " -f1-3 /proc/loadavg)
alone=$(one alone)
echo "alone: $alone s"
one pair_a >"$out/pair_a.wall" &
a=$!
one pair_b >"$out/pair_b.wall" &
b=$!
wait "$a" "$b"
pa=$(cat "$out/pair_a.wall") pb=$(cat "$out/pair_b.wall")
echo "two at once: $pa s and $pb s"
/usr/bin/python3 -c "
import sys
alone, a, b = float(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3])
print('shared_machine policy %s cores %s duration_s %s alone_s %.1f pair_s %.1f %.1f ratio %.2f load_avg_before \"%s\"'
      % (sys.argv[4], sys.argv[5], sys.argv[6], alone, a, b, max(a, b) / alone, sys.argv[7]))
" "$alone" "$pa" "$pb" "${policy:-default}" "$(nproc)" "$duration" "$load0"
