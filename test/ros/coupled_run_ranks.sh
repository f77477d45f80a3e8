#!/usr/bin/env bash
# dem_node on 2 MPI ranks (issue 25): rank 0 talks ROS to mbd_node, rank 1 steps its azimuthal sector of the charge.
#  1. The quick-demo case of coupled_run.sh with dem_node started by mpirun -np 2: the same checks as the one-process
#     run (check_coupled_run.py: every topic of both nodes, no coupling step missing or duplicated, the wrench applied
#     is the one sent, mass balance, PSD), and the log says the charge is on 2 ranks.
#  2. `crusher run --load dem --ranks 2` as a user runs it, stopped by SIGTERM after a checkpoint (rank 0 closes its
#     bag, the ranks stop, the bags are merged), then resumed with --resume --ranks 2 to its end (exit 0).
source "$(dirname "$0")/ros_env.bash"
export OMP_WAIT_POLICY=passive OMP_NUM_THREADS=1
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl_vader_single_copy_mechanism=none

/usr/bin/python3 - "$src/launch_free_configs/quick_demo.yaml" "$out/case.yaml" "$out/case_ck.yaml" <<'PY'
import sys, yaml
c = yaml.safe_load(open(sys.argv[1]))
c["run"].update(duration_s=0.4, settle_s=0.2, tf_hz=20)
c["dem"]["feed"].update(max_fed_kg=6.0, drop_speed_m_s=3.0)
yaml.safe_dump(c, open(sys.argv[2], "w"))
c["run"].update(duration_s=0.16, settle_s=0.05, checkpoint_every_s=0.02)
c["run"].pop("coupled", None)
yaml.safe_dump(c, open(sys.argv[3], "w"))
PY
start_master
mpirun -np 2 --oversubscribe --bind-to none "$CRUSHER_BUILD_DIR/../devel/lib/inertia_crusher/dem_node" \
  _config:="$out/case.yaml" _out:="$out/run" >"$out/dem.log" 2>&1 &
dem_pid=$!
pids+=($dem_pid)
sleep 1
rosrun inertia_crusher mbd_node _config:="$out/case.yaml" _out:="$out/run" >"$out/mbd.log" 2>&1 ||
  { tail -n 20 "$out/mbd.log" "$out/dem.log"; echo "FAIL: mbd_node failed"; exit 1; }
wait "$dem_pid" || { tail -n 20 "$out/dem.log"; echo "FAIL: dem_node on 2 ranks failed"; exit 1; }
grep -q "the charge on 2 MPI ranks" "$out/dem.log" || { tail -n 20 "$out/dem.log"; echo "FAIL: dem_node did not run on 2 ranks"; exit 1; }
grep -h "simulated" "$out/mbd.log" "$out/dem.log" | sed 's/\x1b\[[0-9;]*m//g'
cp "$out/run/run.bag" "$out/run/mbd.bag"
rosrun inertia_crusher merge_bags "$out/run/run.bag" "$out/run/dem.bag" || { echo "FAIL: merge_bags failed"; exit 1; }
/usr/bin/python3 "$src/test/ros/check_coupled_run.py" "$out/run"

# 2. Stopped after its first checkpoints, then resumed on 2 ranks.
"$src/scripts/crusher" run "$out/case_ck.yaml" --load dem --ranks 2 --out "$out/ck" >"$out/ck.log" 2>&1 &
run_pid=$!
for _ in $(seq 1 600); do
  [[ -n $(ls "$out/ck/checkpoint"/dem.*.ckpt 2>/dev/null | sed -n 2p) ]] && break
  kill -0 "$run_pid" 2>/dev/null || break
  sleep 0.1
done
kill -TERM "$run_pid" 2>/dev/null || true
rc=0; wait "$run_pid" || rc=$?
[[ $rc == 143 ]] || { tail -n 30 "$out/ck.log"; echo "FAIL: the stopped 2-rank run exited $rc, not 143 (SIGTERM)"; exit 1; }
grep -q "dem_node: stopped by a signal" "$out/ck.log" || { tail -n 30 "$out/ck.log"; echo "FAIL: rank 0 did not close its bag on SIGTERM"; exit 1; }
pgrep -f "devel/lib/inertia_crusher/dem_node" >/dev/null && { echo "FAIL: dem_node ranks left running after the stop"; exit 1; }
"$src/scripts/crusher" run "$out/case_ck.yaml" --load dem --ranks 2 --out "$out/ck" --resume >"$out/ck2.log" 2>&1 ||
  { tail -n 30 "$out/ck2.log"; echo "FAIL: the 2-rank run did not resume"; exit 1; }
grep -q "dem_node: resumed from the checkpoint" "$out/ck2.log" || { echo "FAIL: no resume in the log"; exit 1; }
grep -h "dem_node: 0.160 s simulated" "$out/ck2.log" >/dev/null || { tail -n 20 "$out/ck2.log"; echo "FAIL: the resumed run did not reach 0.16 s"; exit 1; }
echo "PASS: coupled run with dem_node on 2 MPI ranks; stopped and resumed on 2 ranks"
