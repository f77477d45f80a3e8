#!/usr/bin/env bash
# `crusher calibrate --out DIR`, the whole command as a user runs it (issue 22: it stopped every time with a "DEM
# blow-up at step 9544" in the single-particle tests, and no test ran it): the Taguchi DOE, the confirmation and the
# four single-particle tests all finish (about 20 s on 2 idle cores), exit 0; the calibration reproduces the shipped
# launch_free_configs/bpm_calibrated.yaml (it was written by this command); no blow-up dump is left in the run's
# folder, where one would go.
source "$(dirname "$0")/ros_env.bash"
export OMP_WAIT_POLICY=passive
crusher() { CRUSHER_NO_BUILD=1 bash "$src/scripts/crusher" "$@"; }

start=$SECONDS
crusher calibrate --out "$out/cal" >"$out/cal.log" 2>&1 || { tail -n 30 "$out/cal.log"; echo "FAIL: crusher calibrate failed"; exit 1; }
echo "crusher calibrate: $((SECONDS - start)) s"
grep -c "^single particle [1-4] " "$out/cal.log" | grep -qx 4 || { cat "$out/cal.log"; echo "FAIL: not 4 single-particle tests"; exit 1; }
for f in bpm_calibrated.yaml calibration_summary.json confirmation.json doe_runs.csv anova.csv curves/single_particle_4.csv \
    force_curves_single_particle.png; do
  [[ -s $out/cal/$f ]] || { ls -R "$out/cal"; echo "FAIL: $f missing"; exit 1; }
done
if ls "$out"/cal/blowup_*.csv >/dev/null 2>&1; then echo "FAIL: a blow-up dump in the run's folder"; exit 1; fi
/usr/bin/python3 - "$out/cal" "$src/launch_free_configs/bpm_calibrated.yaml" <<'PY'
import json, math, sys, yaml
out, shipped = sys.argv[1:]
s = json.load(open(out + "/calibration_summary.json"))
forces = s["single_particle_critical_force_kN"]
assert len(forces) == 4 and all(f is not None and math.isfinite(f) and f > 0 for f in forces), forces
assert abs(s["force_error"]) <= 0.05, s["force_error"]
got = yaml.safe_load(open(out + "/bpm_calibrated.yaml"))["bpm"]
want = yaml.safe_load(open(shipped))["bpm"]
for k, v in want["bond"].items():
    assert math.isclose(got["bond"][k], v, rel_tol=1e-6), (k, got["bond"][k], v)
assert got["metaparticles"] == want["metaparticles"] and got["packing"] == want["packing"], (got, want)
print("calibrate: F_c %.3f kN (%+.1f %%), single particles %s kN; bpm_calibrated.yaml as shipped"
      % (s["critical_force_kN"], 100 * s["force_error"], ", ".join("%.2f" % f for f in forces)))
PY
echo "calibrate, the whole command: passed"
