#!/usr/bin/env bash
# make-recording with the diagnosis's new candidates: a mechanism effect with the bed load (bearing_friction raises
# the mean power), a chamber effect with --load flow (worn_liners; its clock starts at 0 after the settle time),
# drive_efficiency under the flow load (the recorded power is the shaft's / efficiency: the same run's power over
# 0.8); a chamber effect without --load flow and an unknown name are refused, naming what is accepted.
set -euo pipefail
crusher=$CRUSHER_SOURCE_DIR/scripts/crusher
cfg=$CRUSHER_SOURCE_DIR/launch_free_configs
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
rec() { CRUSHER_NO_BUILD=1 bash "$crusher" make-recording --seconds 1 --noise-std 0 "$@" >/dev/null; }
mean_power() { python3 -c "import csv,sys; r=list(csv.DictReader(open(sys.argv[1]))); print(sum(float(x['power_W']) for x in r)/len(r))" "$1"; }
rec --config "$cfg/gyp1200_400rpm_bed.yaml" --effect none --out "$out/none.csv"
rec --config "$cfg/gyp1200_400rpm_bed.yaml" --effect bearing_friction --value 0.02 --out "$out/bf.csv"
python3 -c "import sys; a,b=map(float,sys.argv[1:]); sys.exit(0 if b > a + 10e3 else 1)" "$(mean_power "$out/none.csv")" \
  "$(mean_power "$out/bf.csv")" || { echo "FAIL: bearing_friction mu 0.02 did not raise the bed run's power by 10 kW"; exit 1; }
rec --config "$cfg/gyp1200_400rpm.yaml" --load flow --effect none --out "$out/flow.csv"
rec --config "$cfg/gyp1200_400rpm.yaml" --load flow --effect worn_liners --value 10 --out "$out/worn.csv"
head -2 "$out/worn.csv" | tail -1 | grep -q "^0," || { echo "FAIL: the flow recording's clock does not start at 0"; exit 1; }
rec --config "$cfg/gyp1200_400rpm.yaml" --load flow --effect drive_efficiency --value 0.8 --out "$out/de.csv"
python3 -c "import sys; a,b=map(float,sys.argv[1:]); sys.exit(0 if abs(b - a / 0.8) < 1e-6 * b else 1)" \
  "$(mean_power "$out/flow.csv")" "$(mean_power "$out/de.csv")" || { echo "FAIL: drive_efficiency 0.8 is not power / 0.8"; exit 1; }
if msg=$(rec --config "$cfg/gyp1200_400rpm.yaml" --effect feed_limited --value 40 --out "$out/x.csv" 2>&1); then
  echo "FAIL: a chamber effect was accepted without --load flow"; exit 1; fi
grep -q "needs --load flow" <<<"$msg" || { echo "FAIL: chamber effect without --load flow: $msg"; exit 1; }
if msg=$(rec --config "$cfg/gyp1200_400rpm.yaml" --effect bogus --value 1 --out "$out/x.csv" 2>&1); then
  echo "FAIL: an unknown effect was accepted"; exit 1; fi
grep -q "accepted: none, .*bearing_friction, drive_efficiency.*feed_limited, worn_liners" <<<"$msg" || {
  echo "FAIL: unknown effect message: $msg"; exit 1; }
echo "make-recording: bearing_friction (bed), worn_liners and drive_efficiency (--load flow) recorded; bad uses refused"
