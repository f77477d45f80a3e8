#!/usr/bin/env bash
# `crusher demo` end to end as a user runs it (issue 22: every headline command in CI), shortened with its
# --duration option (0.35 s simulated, 0.05 s after the 0.3 s settle; about 35 s wall on 2 cores): exit 0, and what
# the demo promises: one run.bag (dem.bag merged in), summary.json (valid JSON, a coupled run of quick_demo.yaml with
# a product; no whole drive cycle after the settle yet, so no cycle figures), the run's plots and the coupled run's
# CSVs, the Table-5-style summary printed. (coupled_run.sh checks a coupled run's amplitude and power.)
# A --duration the run refuses (not above the settle, not a number) ends the demo non-zero, naming it.
source "$(dirname "$0")/ros_env.bash"
export OMP_WAIT_POLICY=passive CRUSHER_NO_BUILD=1 CRUSHER_BUILD_ROOT=$out/buildroot
t0=$SECONDS
bash "$src/scripts/crusher" demo --duration 0.35 --out "$out/demo" >"$out/demo.log" 2>&1 ||
  { tail -n 30 "$out/demo.log"; echo "FAIL: crusher demo --duration 0.35 exited non-zero"; exit 1; }
echo "crusher demo --duration 0.35: $((SECONDS - t0)) s wall"
grep -q "demo: .*quick_demo.yaml -> $out/demo (0.35 s simulated)" "$out/demo.log" ||
  { tail -n 30 "$out/demo.log"; echo "FAIL: the demo did not say what it runs"; exit 1; }
grep -q "P80 (mm) .*[0-9]" "$out/demo.log" || { tail -n 30 "$out/demo.log"; echo "FAIL: no summary table printed"; exit 1; }
grep -q "no whole drive cycle after the settle yet" "$out/demo.log" ||
  { tail -n 30 "$out/demo.log"; echo "FAIL: the summary has whole drive cycles: the demo ran past 0.35 s"; exit 1; }
for f in run.bag summary.json displacement.png power.png psd.png concave_forces.png force_history.png mantle_path.png \
  particle_paths.png breaks.csv trajectories.csv; do
  [[ -s $out/demo/$f ]] || { ls -l "$out/demo"; tail -n 30 "$out/demo.log"; echo "FAIL: the demo wrote no $f"; exit 1; }
done
[[ ! -e $out/demo/dem.bag ]] || { echo "FAIL: dem.bag was not merged into run.bag"; exit 1; }
/usr/bin/python3 - "$out/demo/summary.json" <<'PY'
import json, sys

def no_constant(c):  # NaN / Infinity are not JSON
    raise ValueError("summary.json holds " + c)

s = json.load(open(sys.argv[1]), parse_constant=no_constant)
assert s["load"] == "dem" and s["config"].endswith("quick_demo.yaml"), (s["load"], s["config"])
assert s["stopped"] is None, s["stopped"]
assert abs(s["simulated_s"] - 0.35) < 2e-3, s["simulated_s"]
assert s["power_kW"]["cycles"] == 0 and s["amplitude_x_mm"]["cycles"] == 0, (s["power_kW"], s["amplitude_x_mm"])
for q in ("amplitude_x_mm", "amplitude_y_mm", "amplitude_z_mm", "power_kW", "drive_speed_rad_s"):
    assert s[q]["mean"] is None and s[q]["std"] is None, (q, s[q])  # no cycle: null, not 0
assert s["specific_energy_kWh_per_t"] is None, s["specific_energy_kWh_per_t"]
psd = s["psd"]
assert len(psd["sieve_mm"]) == len(psd["passing_pct"]) == 11, psd
assert s["mass_crushed_kg"] > 0, s["mass_crushed_kg"]
assert s["mass_discharged_kg"] > 0 and s["throughput_tph"] > 0 and 1 < s["p80_mm"] < 63, s
print("demo summary: %.2f kg crushed, %.2f kg discharged, P80 %.1f mm, %.1f s wall in mbd_node" % (
    s["mass_crushed_kg"], s["mass_discharged_kg"], s["p80_mm"], s["wall_s"]))
PY
# A duration the run refuses ends the demo at once, non-zero, naming the option.
for bad in 0.2 abc; do
  if bash "$src/scripts/crusher" demo --duration "$bad" --out "$out/bad" >"$out/bad.log" 2>&1; then
    echo "FAIL: crusher demo --duration $bad exited 0"; exit 1
  fi
  grep -q -- "--duration" "$out/bad.log" || { cat "$out/bad.log"; echo "FAIL: --duration $bad: no message naming it"; exit 1; }
done
echo "crusher demo: summary and files as promised; bad --duration refused"
