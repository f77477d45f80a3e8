#!/usr/bin/env bash
# `crusher sweep` on the local backend, shortened cases (1.5 s settle, 3 s in all) of the shipped 400 rpm config:
# 0. --help explains the derived values; a --vary key that is a section is refused, named;
# 1. a 3-case speed sweep: sweep.csv's rows equal three single `crusher run`s of the cases' configs (every column
#    but the wall time), the time step follows the speed, the figures and the trend checks come out;
# 2. resumed after one case's summary is lost and the grid extended: only those two cases run;
# 3. a mass sweep with a negative mass: that case is named with its error, the other completes with the inertia
#    scaled by its mass, the exit status is 1;
# 4. stopped by Ctrl-C while running: sweep.csv stays readable, the same command completes it.
source "$(dirname "$0")/ros_env.bash"
crusher="$src/scripts/crusher"
export CRUSHER_NO_BUILD=1  # built by the suite; config_yaml.py calls `crusher config`
fail() { echo "FAIL: $*"; exit 1; }
printf 'base: %s\nrun: {duration_s: 3.0, settle_s: 1.5}\n' "$src/launch_free_configs/gyp1200_400rpm.yaml" >"$out/base.yaml"
sweep() { CRUSHER_NO_BUILD=1 bash "$crusher" sweep "$out/base.yaml" "$@"; }
# 0. --help, a --vary key that is no number
help=$(bash "$crusher" sweep --help) && grep -q "^usage: crusher sweep" <<<"$help" && grep -q "inertia_kg_m2 scales" <<<"$help" ||
  fail "crusher sweep --help: $help"
if msg=$(sweep --vary mbd.drive=1:2:1 --out "$out/bad" 2>&1); then fail "a section as --vary key was accepted"; fi
grep -q "'mbd.drive' is a section, not a number" <<<"$msg" || fail "bad --vary key message: $msg"
# the trend checks on made-up rows: each verdict (holds, partly, FAILS) where it belongs
/usr/bin/python3 - "$src/src/tools" <<'PY' || fail "trend checks"
import sys
sys.path.insert(0, sys.argv[1])
import plot_sweep as p
S, M = p.SPEED, p.MASS
rows = [{S: s, M: m, "amplitude_x_mean_mm": 5 + s / 100 - m / 1e4, "specific_energy_kWh_per_t": 3 - s / 300,
         "p80_mm": 10 + s / 100} for s in (400, 500, 600) for m in (20000, 30000)]
got = {t.split(" (")[0]: w for t, w in p.trends(rows, [S, M])}
assert got == {"amplitude slightly up with speed": "partly", "amplitude down as the fixed-cone mass rises": "holds",
               "specific energy up with speed": "FAILS", "product finer with speed: P80 down": "FAILS"}, got
PY

# 1. three cases against three single runs
sweep --vary mbd.drive.speed_rpm=400:600:100 --jobs 2 --out "$out/s" >"$out/s.log" 2>&1 ||
  { tail -n 30 "$out/s.log"; fail "the 3-case sweep failed"; }
cat "$out/s.log"
for c in 400 500 600; do
  CRUSHER_NO_BUILD=1 bash "$crusher" run "$out/s/cases/speed_rpm_$c/case.yaml" --out "$out/single/$c" \
    >"$out/single$c.log" 2>&1 || { tail -n 20 "$out/single$c.log"; fail "crusher run of case $c failed"; }
done
/usr/bin/python3 - "$out" <<'PY'
import csv, json, sys
out = sys.argv[1]
rows = list(csv.DictReader(open(out + "/s/sweep.csv")))
assert [r["case"] for r in rows] == ["speed_rpm_400", "speed_rpm_500", "speed_rpm_600"], rows
cols = {"amplitude_x_mean_mm": "amplitude_x_mm.mean", "amplitude_x_std_mm": "amplitude_x_mm.std",
        "power_mean_kW": "power_kW.mean", "power_std_kW": "power_kW.std", "throughput_tph": "throughput_tph",
        "specific_energy_kWh_per_t": "specific_energy_kWh_per_t", "p80_mm": "p80_mm",
        "passing_12mm_pct": "passing_12mm_pct", "passing_1mm_pct": "passing_1mm_pct"}
for r, rpm in zip(rows, (400, 500, 600)):
    assert r["status"] == "ok" and float(r["mbd.drive.speed_rpm"]) == rpm, r
    s = json.load(open(f"{out}/single/{rpm}/summary.json"))
    for col, path in cols.items():
        v = s
        for k in path.split("."):
            v = v[k]
        assert r[col] != "" and float(r[col]) == float(f"{v:.8g}"), (rpm, col, r[col], v)
    speed = s["drive_speed_rad_s"]["mean"] * 30 / 3.141592653589793
    assert abs(speed - rpm) < 0.01 * rpm, (rpm, speed)  # the case ran at its speed
    case = open(f"{out}/s/cases/speed_rpm_{rpm}/case.yaml").read()
    assert f"time_step_s: {0.001 if rpm == 400 else 0.0005}" in case, case  # w dt <= 0.042 rad, whole steps
print("sweep.csv rows equal the three single runs; the time step follows the speed")
PY
for f in fig22_amplitude.png fig23_psd.png fig24_specific_energy.png; do [[ -s $out/s/$f ]] || fail "$f missing"; done
grep -q "amplitude slightly up with speed" "$out/s.log" || fail "no trend check printed"
ls "$out"/s/cases/*/run.bag 2>/dev/null && fail "run.bag kept without --bag"

# 2. resume: one summary lost, the grid extended to 700 rpm: exactly those two run
rm "$out/s/cases/speed_rpm_500/summary.json"
sweep --vary mbd.drive.speed_rpm=400:700:100 --jobs 2 --out "$out/s" --no-plots >"$out/r.log" 2>&1 ||
  { cat "$out/r.log"; fail "the resumed sweep failed"; }
cat "$out/r.log"
grep -q "4 cases (4 mbd.drive.speed_rpm), 2 already done, 2 to run" "$out/r.log" || fail "resume: wrong count"
ran=$(grep -oE '^\[sweep\] [0-9]+/4 [^:]+' "$out/r.log" | awk '{print $3}' | sort | tr '\n' ' ')
[[ $ran == "speed_rpm_500 speed_rpm_700 " ]] || fail "resume ran '$ran', expected speed_rpm_500 speed_rpm_700"
[[ $(grep -c ',ok,' "$out/s/sweep.csv") == 4 ]] || fail "resume: not 4 ok rows"

# 3. a failing case among good ones; the derived inertia of the other
if sweep --vary mbd.fixed_cone.mass_kg=-1000,12062.2 --out "$out/m" --no-plots >"$out/m.log" 2>&1; then
  fail "a sweep with a failed case exited 0"
fi
cat "$out/m.log"
grep -q "FAILED mass_kg_-1000: .*mbd.fixed_cone.mass_kg.*-1000" "$out/m.log" || fail "the failed case is not named with its error"
/usr/bin/python3 - "$out" "$src/scripts" <<'PY'
import csv, json, sys
sys.path.insert(0, sys.argv[2])
import config_yaml
out = sys.argv[1]
rows = {r["case"]: r for r in csv.DictReader(open(out + "/m/sweep.csv"))}
assert rows["mass_kg_12062.2"]["status"] == "ok", rows
assert "mbd.fixed_cone.mass_kg" in rows["mass_kg_-1000"]["status"] and rows["mass_kg_-1000"]["amplitude_x_mean_mm"] == "", rows
c = config_yaml.load(out + "/m/cases/mass_kg_12062.2/case.yaml")
base = config_yaml.load(out + "/base.yaml")
fc, fc0 = c["mbd"]["fixed_cone"], base["mbd"]["fixed_cone"]
assert fc["mass_kg"] == 12062.2, fc
for i, i0 in zip(fc["inertia_kg_m2"], fc0["inertia_kg_m2"]):
    assert abs(i - i0 * 12062.2 / 24124.4) < 1e-6 * i0, (fc, fc0)  # half the mass, half the inertia
assert c["mbd"]["time_step_s"] == base["mbd"]["time_step_s"]  # the speed was not varied
print("the failed case is reported with its error; the new mass has half the inertia")
PY

# 4. stopped while running (Ctrl-C: SIGINT to the sweep's process group), then resumed to the end
set -m  # the sweep in a process group of its own, as in a terminal
CRUSHER_NO_BUILD=1 bash "$crusher" sweep "$out/base.yaml" --vary mbd.drive.speed_rpm=300:700:100 --jobs 1 \
  --out "$out/k" --no-plots >"$out/k.log" 2>&1 &
pid=$!
set +m
pids+=("$pid")
for _ in $(seq 1 300); do grep -q '^\[sweep\] 1/5' "$out/k.log" && break; sleep 0.2; done
kill -INT -- -"$pid"
rc=0; wait "$pid" || rc=$?
cat "$out/k.log"
[[ $rc == 130 ]] || fail "a stopped sweep exited $rc, expected 130"
grep -q "interrupted" "$out/k.log" || fail "no interruption message"
/usr/bin/python3 -c '
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert len(rows) == 5 and sum(r["status"] == "ok" for r in rows) >= 1, rows
assert any(r["status"] != "ok" for r in rows), "all done before the stop: the test did not stop it"
' "$out/k/sweep.csv" || fail "sweep.csv after the stop"
pgrep -f "$out/k/cases" >/dev/null && fail "processes of the stopped sweep still run"
sweep --vary mbd.drive.speed_rpm=300:700:100 --jobs 2 --out "$out/k" --no-plots >"$out/k2.log" 2>&1 ||
  { cat "$out/k2.log"; fail "the resumed sweep failed"; }
[[ $(grep -c ',ok,' "$out/k/sweep.csv") == 5 ]] || fail "the resumed sweep did not complete all 5"
echo "sweep check passed"
