#!/usr/bin/env bash
# Integration test of the fast mode (run.load flow) as a user runs it: `crusher run` on the shipped 400 rpm config,
# shortened (2 s settle, 2 s window). Checks the summary (every Table 5 field a number), the product stream in the
# bag (fed = in chamber + discharged, throughput > 0, passing ascending to 100 %) and the liners and chamber cells.
source "$(dirname "$0")/ros_env.bash"
/usr/bin/python3 - "$src/launch_free_configs/gyp1200_400rpm.yaml" "$out/case.yaml" <<'PY'
import sys, yaml
c = yaml.safe_load(open(sys.argv[1]))
c["run"].update(duration_s=4.0, settle_s=2.0)
yaml.safe_dump(c, open(sys.argv[2], "w"))
PY
CRUSHER_NO_BUILD=1 bash "$src/scripts/crusher" run "$out/case.yaml" --out "$out/run" >"$out/run.log" 2>&1 ||
  { tail -n 30 "$out/run.log"; echo "FAIL: crusher run failed"; exit 1; }
cat "$out/run.log" | tail -n 25
/usr/bin/python3 - "$out/run" "$out/run.log" <<'PY'
import json, os, re, sys
import rosbag
run = sys.argv[1]
s = json.load(open(run + "/summary.json"))
assert s["load"] == "flow", s["load"]
for k in ("throughput_tph", "specific_energy_kWh_per_t", "p80_mm", "passing_12mm_pct", "passing_1mm_pct"):
    assert isinstance(s[k], (int, float)), (k, s[k])
assert s["throughput_tph"] > 1, s["throughput_tph"]
assert abs(s["specific_energy_kWh_per_t"] - s["power_kW"]["mean"] / s["throughput_tph"]) < 1e-6
assert s["amplitude_x_mm"]["mean"] > 0.5 and s["power_kW"]["mean"] > 1
p = s["psd"]["passing_pct"]
assert all(b >= a for a, b in zip(p, p[1:])) and abs(p[-1] - 100) < 1e-9, p
with rosbag.Bag(run + "/run.bag") as bag:
    topics = bag.get_type_and_topic_info().topics
    for t in ("/crusher/product", "/crusher/liners", "/crusher/chamber", "/crusher/test_point", "/tf",
              "/crusher/concave_forces"):
        assert t in topics, (t, sorted(topics))
    assert topics["/crusher/product"].message_count == topics["/tf"].message_count
    last = None
    for _, m, _ in bag.read_messages(topics=["/crusher/product"]):
        fed, held, out = m.mass_fed_kg, m.mass_in_chamber_kg, m.mass_discharged_kg
        assert abs(fed - held - out) <= 1e-9 * fed, (fed, held, out)
        last = m
    assert last.throughput_tph > 1 and last.mass_discharged_kg > 10, (last.throughput_tph, last.mass_discharged_kg)
    for _, m, _ in bag.read_messages(topics=["/crusher/liners"]):
        assert [k.ns for k in m.markers] == ["mantle", "concave"] and len(m.markers[0].points) % 3 == 0
        break
    n = 0
    for _, m, _ in bag.read_messages(topics=["/crusher/concave_forces"]):
        assert (m.rings, m.sectors, len(m.mean_normal_force)) == (13, 9, 117), (m.rings, m.sectors)
        assert m.window_s > 0 and min(m.mean_normal_force) >= 0, (m.window_s, min(m.mean_normal_force))
        n += sum(m.mean_normal_force) > 0
    assert n > 10, "the force map never carried a force"
# The printed table shows summary.json's own P80 (not one recomputed from the sieves); every plot is written.
printed = re.search(r"P80 \(mm\)\s+(\S+)", open(sys.argv[2]).read()).group(1)
assert printed == "%.2f" % s["p80_mm"], (printed, s["p80_mm"])
for png in ("displacement", "power", "psd", "concave_forces", "force_history", "mantle_path"):
    assert os.path.getsize(os.path.join(run, png + ".png")) > 1000, png
print("flow run: %.2f mm, %.1f kW, %.1f t/h, %.2f kWh/t, P80 %.1f mm; product stream balanced" % (
    s["amplitude_x_mm"]["mean"], s["power_kW"]["mean"], s["throughput_tph"], s["specific_energy_kWh_per_t"],
    s["p80_mm"]))
PY
echo "flow run check passed"
