#!/usr/bin/env bash
# `crusher flow-bench --end-to-end` (issue 20's benchmark: the fast mode's real time for the library and for
# `crusher run` end to end, at 400 and 600 rpm, and validate's wall time): short runs, one round. Checks that each
# row reports the simulated seconds asked for and a real-time factor that is its own simulated / wall seconds, and
# that a duration inside the settle is refused by name. Timings are not checked (a benchmark, not a timed test).
source "$(dirname "$0")/ros_env.bash"
export CRUSHER_NO_BUILD=1 CRUSHER_BUILD_ROOT=$out/buildroot
"$src/scripts/crusher" flow-bench --end-to-end --seconds 5 --rounds 1 >"$out/e2e.log" 2>&1 ||
  { tail -n 30 "$out/e2e.log"; echo "FAIL: flow-bench --end-to-end failed"; exit 1; }
cat "$out/e2e.log"
/usr/bin/python3 - "$out/e2e.log" <<'PY'
import re, sys
text = open(sys.argv[1]).read()
for rpm in (400, 600):
    row = re.search(r"^%d rpm +(.*)$" % rpm, text, re.M)
    assert row, "no %d rpm row" % rpm
    cells = re.findall(r"([0-9.]+) s in ([0-9.]+)-([0-9.]+) s: +([0-9.]+)x", row.group(1))
    assert len(cells) == 2, row.group(0)  # the library and the node
    for sim, lo, hi, rtf in cells:
        assert abs(float(sim) - 5.0) < 0.01, (rpm, sim)
        assert 0 < float(lo) <= float(hi) and abs(float(rtf) - float(sim) / float(lo)) < 0.06 * float(rtf), (rpm, cells)
m = re.search(r"crusher validate \(both speeds, with its plots\): ([0-9.]+) s$", text, re.M)
assert m and float(m.group(1)) > 0, "no validate wall time"
PY
if "$src/scripts/crusher" flow-bench --end-to-end --seconds 3 >"$out/bad.log" 2>&1; then
  echo "FAIL: --seconds 3 (inside the 4 s settle) was accepted"; exit 1
fi
grep -q "seconds 3.0: accepted a number above the 4 s settle" "$out/bad.log" || { cat "$out/bad.log"; echo "FAIL: the refusal"; exit 1; }
echo "flow_bench_e2e: both speeds' rows and validate's wall time reported; --seconds 3 refused"
