"""crusher flow-bench --end-to-end: the fast mode's real-time factor at 400 and 600 rpm, for the library alone
(flow_bench, no ROS) and for `crusher run` end to end (mbd_node with its topics and bag: summary.json's wall_s), the
same simulated seconds, rounds alternated; then `crusher validate`'s wall time for both speeds. A benchmark, not a
test: run it on an idle machine (two runs at once on 2 cores give nonsense ratios)."""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time


def main():
    p = argparse.ArgumentParser(prog="crusher flow-bench --end-to-end", description=__doc__)
    p.add_argument("--repo", required=True)
    p.add_argument("--flow-bench", required=True, help="the flow_bench executable")
    p.add_argument("--seconds", type=float, default=40.0, help="simulated seconds per run (default 40, the configs')")
    p.add_argument("--rounds", type=int, default=3, help="rounds, each speed's library and node runs alternated (3)")
    a = p.parse_args()
    if not (a.seconds > 4.0):
        sys.exit("flow-bench --end-to-end: --seconds %s: accepted a number above the 4 s settle" % a.seconds)
    if a.rounds < 1:
        sys.exit("flow-bench --end-to-end: --rounds %s: accepted a whole number >= 1" % a.rounds)
    crusher = os.path.join(a.repo, "scripts", "crusher")
    env = dict(os.environ, CRUSHER_NO_BUILD="1", CRUSHER_RUN_PLOTS="0")
    print("load before: %s" % open("/proc/loadavg").read().split()[:3], flush=True)
    lib = {400: [], 600: []}
    node = {400: [], 600: []}
    with tempfile.TemporaryDirectory(prefix="crusher_flow_bench_") as tmp:
        for r in range(a.rounds):
            for rpm in (400, 600):
                cfg = os.path.join(a.repo, "launch_free_configs", "gyp1200_%drpm.yaml" % rpm)
                out = subprocess.run([a.flow_bench, "--config", cfg, "--seconds", str(a.seconds - 4.0), "--settle", "4"],
                                     capture_output=True, text=True, check=True).stdout
                m = re.search(r"simulated_s ([0-9.]+) wall_s ([0-9.]+)", out)
                lib[rpm].append((float(m.group(1)), float(m.group(2))))
                run = os.path.join(tmp, "run_%d_%d" % (rpm, r))
                res = subprocess.run([crusher, "run", cfg, "--out", run, "--duration", str(a.seconds)], env=env,
                                     capture_output=True, text=True)
                if res.returncode != 0:
                    sys.exit("flow-bench --end-to-end: crusher run %s failed:\n%s" % (cfg, res.stderr[-2000:]))
                s = json.load(open(os.path.join(run, "summary.json")))
                node[rpm].append((float(s["simulated_s"]), float(s["wall_s"])))
        t0 = time.monotonic()
        res = subprocess.run([crusher, "validate", "--out", os.path.join(tmp, "validate")], env=env,
                             capture_output=True, text=True)
        validate_s = time.monotonic() - t0
    print("load after: %s" % open("/proc/loadavg").read().split()[:3])
    print("\nthe flow mode's real time, one core each (min over %d rounds; wall s: min-max)" % a.rounds)
    print("%-6s %-36s %-36s" % ("speed", "library (flow_bench)", "end to end (crusher run: mbd_node)"))
    for rpm in (400, 600):
        row = []
        for runs in (lib[rpm], node[rpm]):
            sim = runs[0][0]
            walls = [w for _, w in runs]
            row.append("%5.1f s in %.3f-%.3f s: %5.1fx" % (sim, min(walls), max(walls), sim / min(walls)))
        print("%-6s %-36s %-36s" % ("%d rpm" % rpm, row[0], row[1]))
    print("crusher validate (both speeds, with its plots): %.1f s%s" %
          (validate_s, "" if res.returncode == 0 else " (it failed: %s)" % res.stderr.strip()[-300:]))


if __name__ == "__main__":
    main()
