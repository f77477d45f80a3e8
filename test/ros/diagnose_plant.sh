#!/usr/bin/env bash
# The diagnosis reads a plant (DAQ) export through a column map: the base model's own output written as one
# (semicolon, decimal comma, ms / mm / kW / rpm, speed logged at its set point, values rounded to the logger's
# steps, NaN rows, a gap, 500 Hz) must be diagnosed as `none`, the set point and the skipped rows reported; a
# file read with the wrong delimiter is refused naming the column and the delimiter to give; one recording over two
# files (--part) from displacement sensors not zeroed at rest (--zero-unknown) is `none` too.
source "$(dirname "$0")/ros_env.bash"
cd "$out"
bin=$(dirname "$(catkin_find --first-only --libexec inertia_crusher diagnose)")
cfg=$src/launch_free_configs/gyp1200_400rpm_bed.yaml
cols='t=Zeit[ms],x=Weg_X[mm],y=Weg_Y[mm],z=Weg_Z[mm],power=P_el[kW],speed=n[rpm]'
"$bin/make_recording" --config "$cfg" --effect none --seconds 4 --seed 8 --time-offset-s 0.04 --columns "$cols" \
  --delimiter ';' --decimal , --resolution x=0.01,y=0.01,z=0.01,power=0.1,speed=1 --speed-setpoint --missing-rows 5 \
  --gap 1.5:0.2 --sample-hz 500 --out plant.csv >/dev/null
head -n 2 plant.csv
grep -q '^Zeit\[ms\];Weg_X\[mm\]' plant.csv || { echo "FAIL: the export's header: $(head -n 1 plant.csv)"; exit 1; }
"$bin/diagnose" --recording plant.csv --config "$cfg" --columns "$cols" --delimiter ';' --decimal , \
  --out diag >diag.log 2>&1 || { tail -n 20 diag.log; echo "FAIL: diagnose exited non-zero"; exit 1; }
cat diag.log
# The plots show the channels compared (the speed set point has no model curve).
grep -q "plotting failed" diag.log && { echo "FAIL: the plots failed"; exit 1; }
ls diag/overlay_0.png diag/residual_spectrum.png >/dev/null || { echo "FAIL: no plots"; exit 1; }
/usr/bin/python3 - diag/diagnosis.json <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert d["effect"] == "none", f"the model's own output as a plant export was diagnosed as {d['effect']}: {d['reason']}"
i = d["inputs"][0]
assert i["channels"]["speed_rad_s"]["use"] == "set point", i
assert abs(i["channels"]["x_m"]["resolution"] - 1e-5) < 1e-11, i
assert any("with a missing value skipped" in n for n in i["notes"]), i["notes"]
assert any("gap(s)" in n for n in i["notes"]), i["notes"]
assert "speed_rad_s" not in d["metrics"]["before"]["train"][0]["channels"]
print("plant export diagnosed as none; speed taken as a set point; rows and gap reported")
PY
grep -q "speed_rad_s = 41.88790" diag/report.md || { echo "FAIL: report.md does not show the set point"; exit 1; }
if msg=$("$bin/diagnose" --recording plant.csv --config "$cfg" --columns "$cols" --out bad 2>&1); then
  echo "FAIL: a ';'-separated file read at ',' was accepted"; exit 1; fi
grep -q "column 'Zeit' (t) is not in the header.*--delimiter ';'" <<<"$msg" || { echo "FAIL: the message: $msg"; exit 1; }
# The same recording logged over two files by a sensor not zeroed at rest: --part joins them (the time between them
# kept as a gap), --zero-unknown leaves the displacements' means out; still none.
"$bin/make_recording" --config "$cfg" --effect none --seconds 4 --seed 9 --time-offset-s 0.02 --columns "$cols" \
  --delimiter ';' --decimal , --zero-offset-mm 1.3,-0.8,2.1 --sample-hz 500 --out zero.csv >/dev/null
head -n 1 zero.csv >part1.csv && sed -n '2,1001p' zero.csv >>part1.csv
head -n 1 zero.csv >part2.csv && sed -n '1102,$p' zero.csv >>part2.csv
"$bin/diagnose" --recording part1.csv --part part2.csv --zero-unknown x,y,z --config "$cfg" --columns "$cols" \
  --delimiter ';' --decimal , --no-plots --out parts >parts.log 2>&1 || { tail -n 20 parts.log; echo "FAIL: diagnose --part"; exit 1; }
/usr/bin/python3 - parts/diagnosis.json <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert d["effect"] == "none", f"two parts of the model's own output, zero offsets: {d['effect']}: {d['reason']}"
i = d["inputs"][0]
assert any("joined part" in n and "a gap, kept" in n for n in i["notes"]), i["notes"]
assert i["channels"]["x_m"]["mean"] == "not compared (sensor zero unknown)", i["channels"]["x_m"]
print("two parts joined, sensor zero unknown: none")
PY
echo "diagnosis of a plant export: passed"
