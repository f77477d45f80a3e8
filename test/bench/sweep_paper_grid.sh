#!/usr/bin/env bash
# Benchmark (not a test): the paper's design grid in the fast mode (section 4.3: drive speed 300-700 rpm in 50 rpm
# steps x fixed-cone mass 10-50 t in 5 t steps, 81 cases of the shipped 400 rpm config, 10 s simulated each) through
# `crusher sweep` on this machine's cores; prints the wall time. Usage: test/bench/sweep_paper_grid.sh [OUT] [--jobs N]
set -euo pipefail
repo=$(cd "$(dirname "$0")/../.." && pwd)
out=${1:-$(mktemp -d)/paper_grid}
shift || true
rm -rf "$out"
LOAD0=$(cut -d" " -f1-3 /proc/loadavg)  # the machine may be shared: say how busy it was
t0=$(date +%s.%N)
rc=0
"$repo/scripts/crusher" sweep "$repo/launch_free_configs/gyp1200_400rpm.yaml" --vary mbd.drive.speed_rpm=300:700:50 \
  --vary mbd.fixed_cone.mass_kg=10000:50000:5000 --out "$out" "$@" || rc=$?
t1=$(date +%s.%N)
ok=$(grep -c ',ok,' "$out/sweep.csv" || true)
solver=$(/usr/bin/python3 -c 'import csv,sys; print("%.0f" % sum(float(r["wall_s"] or 0) for r in csv.DictReader(open(sys.argv[1]))))' "$out/sweep.csv")
printf 'sweep_paper_grid cases 81 ok %s cores %s wall_s %.0f solver_s %s load_avg_before "%s" out %s\n' \
  "$ok" "$(nproc)" "$(/usr/bin/python3 -c "print($t1 - $t0)")" "$solver" "$LOAD0" "$out"
exit $rc
