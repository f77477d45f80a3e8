#!/usr/bin/env bash
# `crusher validate` end to end as a user runs it (issue 22: every headline command in CI), shortened (3 s window):
# exit 0, and its report: validation.json with the model's Table 5 figures at both speeds (numbers, 400 rpm marked
# calibrated, the plant's and the paper's values beside them), the section 4.3 trends, validation.txt and the PNG.
source "$(dirname "$0")/ros_env.bash"
CRUSHER_NO_BUILD=1 bash "$src/scripts/crusher" validate --seconds 3 --out "$out/v" >"$out/v.log" 2>&1 ||
  { tail -n 30 "$out/v.log"; echo "FAIL: crusher validate exited non-zero"; exit 1; }
/usr/bin/python3 - "$out/v" <<'PY'
import json, math, os, sys
d = sys.argv[1]
j = json.load(open(d + "/validation.json"))
assert j["load"] == "flow" and j["simulated_s"] == 7 and j["settle_s"] == 4, (j["load"], j["simulated_s"], j["settle_s"])
rows = {r["quantity"]: r for r in j["rows"]}
for q in ("amplitude_x_mm_mean", "power_kW_mean", "throughput_tph", "specific_energy_kWh_per_t"):
    r = rows[q]
    for k in ("exp400", "sim400", "ours400", "exp600", "sim600", "ours600", "error600", "paper_error600"):
        assert isinstance(r[k], (int, float)) and math.isfinite(r[k]), (q, k, r[k])
    assert abs(r["error600"] - (r["ours600"] / r["exp600"] - 1)) < 1e-4, (q, r)  # both written to 6 digits
    assert r["calibrated400"] == (q != "specific_energy_kWh_per_t"), (q, r["calibrated400"])
for q in ("p80_mm", "passing_12mm_pct", "passing_1mm_pct"):
    assert rows[q]["ours400"] > 0 and rows[q]["ours600"] > 0, rows[q]
assert set(j["trends"]) == {"power_up", "throughput_down", "product_finer"}, j["trends"]
for e in (j["extra400"], j["extra600"]):  # how the product leaves, and the liners' metal contact: shares in %
    assert 0 <= e["extruded_product_pct"] <= 100 and 0 <= e["cone_contact_pct"] <= 100, e
text = open(d + "/validation.txt").read()
assert "Table 5" in text and "trends 400 -> 600 rpm" in text and "liners in metal contact" in text, text[:300]
assert os.path.getsize(d + "/validation.png") > 10000
print("validate: %.2f mm, %.1f kW, %.1f t/h at 600 rpm; trends %s" % (
    rows["amplitude_x_mm_mean"]["ours600"], rows["power_kW_mean"]["ours600"], rows["throughput_tph"]["ours600"],
    j["trends"]))
PY
echo "crusher validate: report written, every Table 5 figure a number, trends checked"
