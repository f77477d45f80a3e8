#!/usr/bin/env bash
# `crusher config`: --keys prints the schema's key reference, naming every key the shipped configs give in the
# schema sections; --json prints a config resolved (base chain) and validated, which the Python tools read
# (scripts/config_yaml.py); a duplicate or out-of-range key is refused by name.
source "$(dirname "$0")/ros_env.bash"
export CRUSHER_NO_BUILD=1
crusher=$src/scripts/crusher
keys=$(bash "$crusher" config --keys) || { echo "FAIL: crusher config --keys exited non-zero"; exit 1; }
# Every leaf key of the shipped configs is in the reference (but dem.bpm, the BPM's own mapping: src/rocks).
/usr/bin/python3 - "$src/launch_free_configs" "$keys" <<'PY' || exit 1
import sys, yaml
names = {l.split()[0] for l in sys.argv[2].splitlines()[1:] if l.strip()}
def leaves(node, path):
    if isinstance(node, dict):
        for k, v in node.items():
            yield from leaves(v, f"{path}.{k}")
    else:
        yield path
missing = []
for f in ["gyp1200_400rpm.yaml", "gyp1200_400rpm_bed.yaml", "quick_demo.yaml"]:
    c = yaml.safe_load(open(f"{sys.argv[1]}/{f}"))
    for sec in ["run", "mbd", "coupling", "flow", "dem"]:
        missing += [p for p in leaves(c.get(sec, {}), sec) if p not in names and not p.startswith("dem.bpm.")]
if missing or len(names) < 120:
    sys.exit(f"FAIL: crusher config --keys lacks {missing} ({len(names)} keys listed)")
PY
grep -q "^run.settle_s .* s .*\[0, 3600\] .* 1 " <<<"$keys" || { echo "FAIL: run.settle_s line: $(grep settle_s <<<"$keys")"; exit 1; }
only=$(bash "$crusher" config --keys coupling)
[[ $(grep -c '^coupling\.' <<<"$only") == 3 && $(grep -vc '^coupling\.' <<<"$only") == 1 ]] ||
  { echo "FAIL: crusher config --keys coupling: $only"; exit 1; }
if bash "$crusher" config --keys nosuch 2>/dev/null; then echo "FAIL: an unknown section was accepted"; exit 1; fi
# --json: the 600 rpm config through its base, through the Python reader.
/usr/bin/python3 - "$src/scripts" "$src/launch_free_configs/gyp1200_600rpm.yaml" <<'PY' || exit 1
import sys
sys.path.insert(0, sys.argv[1])
import config_yaml
c = config_yaml.load(sys.argv[2])
assert c["mbd"]["drive"]["speed_rpm"] == 600 and c["mbd"]["time_step_s"] == 5e-4, c["mbd"]
assert c["run"]["load"] == "flow" and c["run"]["settle_s"] == 4 and c["run"]["tf_hz"] == 50, c["run"]
assert "base" not in c and c["flow"]["material"]["pressure"]["exponent"] == 2.8686, c["flow"]
assert c["coupling"]["dt_s"] == 0.001 and c["flow"]["prefill"] is True, c
assert c["mbd"]["effects"]["motor_droop"]["enabled"] is False and c["mbd"]["chamber"]["concave_r_mm"] == [229.8, 667.3481], c
PY
printf 'base: %s\nrun:\n  load: flow\n  load: bed\n' "$src/launch_free_configs/gyp1200_400rpm.yaml" >"$out/dup.yaml"
if msg=$(bash "$crusher" config --json "$out/dup.yaml" 2>&1); then echo "FAIL: a duplicate key was accepted"; exit 1; fi
grep -q "key 'run.load' appears twice" <<<"$msg" || { echo "FAIL: duplicate key message: $msg"; exit 1; }
printf 'base: %s\nflow:\n  bands: 1\n' "$src/launch_free_configs/gyp1200_400rpm.yaml" >"$out/bad.yaml"
if msg=$(/usr/bin/python3 "$src/scripts/config_yaml.py" "$out/bad.yaml" run.load 2>&1); then
  echo "FAIL: flow.bands 1 was accepted by config_yaml.py"; exit 1; fi
grep -q "'flow.bands'" <<<"$msg" || { echo "FAIL: out-of-range message: $msg"; exit 1; }
echo "crusher config: --keys lists every key, --json resolves and validates, bad keys refused by name"
