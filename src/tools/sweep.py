#!/usr/bin/env python3
"""crusher sweep: a design study over one or two config keys; each case is one `crusher run`."""
import argparse
import json
import os
import re
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sweep_cases  # noqa: E402
from sweep_cases import SweepError  # noqa: E402

REPO = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
CRUSHER = os.path.join(REPO, "scripts", "crusher")

HELP = """\
Runs CONFIG over the grid of the --vary values (one or two keys; any numeric key of the merged config, a list
element as KEY[i]); each case is `crusher run DIR/cases/NAME/case.yaml --out DIR/cases/NAME`.

Values that follow a varied one (written into case.yaml with a comment saying why):
  - a body's inertia_kg_m2 scales with its mass_kg (inertia ~ mass at fixed shape), e.g. the fixed cone's
    with mbd.fixed_cone.mass_kg, unless an element of that inertia is varied too;
  - with mbd.drive.speed_rpm varied, mbd.time_step_s = coupling.dt_s / n, n the smallest whole number that keeps
    the drive rotation per step w dt at or below the base config's (0.042 rad for gyp1200_400rpm.yaml; the
    mechanism refuses > 0.05 rad): the coupling interval stays whole steps. Varying mbd.time_step_s turns it off.

Outputs in DIR:
  sweep.csv         one row per case: varied values, amplitude x mean/std (mm), power mean/std (kW), throughput
                    (t/h), specific energy (kWh/t), P80 (mm), passing 12 mm and 1 mm (%), wall_s (the solver's,
                    from summary.json; the case's whole time when it failed), status (ok, the error, pending),
                    case. Rewritten after each case.
  cases/NAME/       case.yaml, summary.json, run.log, status.json; run.bag only with --bag (the run's own
                    plots are left out: `crusher run cases/NAME/case.yaml --out D` makes them)
  fig22_amplitude.png, fig23_psd.png, fig24_specific_energy.png   the paper's Figures 22-24 (plot_sweep.py),
                    the plant's Table 5 points (400 and 600 rpm, 24.1 t) marked; then the paper's trends, checked.
Resumable: a case whose summary.json is complete for the same case.yaml and options is skipped. A failed case
is named with its error and the others go on (exit status 1 at the end). Ctrl-C stops the running cases and
leaves sweep.csv readable; the same command resumes.
Backends: local (default; --jobs processes, default the number of cores) or slurm (one job array submitted
with sbatch, the cases run on the cluster's nodes from this repository's build, which must be on a shared
file system; collected when done; --partition, --time, --cpus-per-case)."""

COLUMNS = [  # (sweep.csv column, summary.json path)
    ("amplitude_x_mean_mm", "amplitude_x_mm.mean"), ("amplitude_x_std_mm", "amplitude_x_mm.std"),
    ("power_mean_kW", "power_kW.mean"), ("power_std_kW", "power_kW.std"),
    ("throughput_tph", "throughput_tph"), ("specific_energy_kWh_per_t", "specific_energy_kWh_per_t"),
    ("p80_mm", "p80_mm"), ("passing_12mm_pct", "passing_12mm_pct"), ("passing_1mm_pct", "passing_1mm_pct"),
    ("wall_s", "wall_s"),
]


def number(kind, lo, hi):
    """An argparse type: a finite number of `kind` (int or float) in [lo, hi], else an error naming the value and
    the range (issue 22: every numeric flag checked)."""
    def parse(text):
        try:
            x = kind(text)
        except ValueError:
            x = None
        if x is None or x != x or not lo <= x <= hi:
            what = "a whole number" if kind is int else "a number"
            raise argparse.ArgumentTypeError(f"{text!r}: accepted {what} in [{lo:g}, {hi:g}]")
        return x
    return parse


def parse_args(argv):
    p = argparse.ArgumentParser(prog="crusher sweep", description=HELP, formatter_class=argparse.RawDescriptionHelpFormatter,
                                usage="crusher sweep CONFIG --vary KEY=FROM:TO:STEP [--vary KEY=...] --out DIR "
                                      "[--jobs N] [--load none|bed|flow|dem] [--duration S] [--ranks N] [--bag] "
                                      "[--backend local|slurm [--partition P] [--time T] [--cpus-per-case N]] [--no-plots]")
    p.add_argument("config", metavar="CONFIG")
    p.add_argument("--vary", action="append", required=True, metavar="KEY=FROM:TO:STEP",
                   help="a key and its values (TO included when reached; or KEY=V1,V2,...); once or twice")
    p.add_argument("--out", required=True, metavar="DIR")
    p.add_argument("--jobs", type=number(int, 1, 1024), default=os.cpu_count() or 1, help="cases at once (local; default: cores)")
    p.add_argument("--load", choices=["none", "bed", "flow", "dem"], help="passed to crusher run (default: the config's)")
    p.add_argument("--duration", type=number(float, 1e-3, 3600), metavar="S",
                   help="passed to crusher run: simulated seconds per case (run.duration_s's range)")
    p.add_argument("--ranks", type=number(int, 1, 4096), metavar="N",
                   help="load dem: each case's dem_node on N MPI ranks (crusher run --ranks; slurm: N tasks per case)")
    p.add_argument("--bag", action="store_true", help="keep each case's run.bag (removed otherwise)")
    p.add_argument("--backend", choices=["local", "slurm"], default="local")
    p.add_argument("--partition", help="slurm: the partition (default: the cluster's default)")
    p.add_argument("--time", metavar="T", help="slurm: time limit per case, as sbatch --time takes it (e.g. 2:00:00)")
    p.add_argument("--cpus-per-case", type=number(int, 1, 1024), default=1, metavar="N", help="slurm: cores per case (default 1)")
    p.add_argument("--no-plots", action="store_true", help="only sweep.csv (no figures, no trend checks)")
    a = p.parse_args(argv)
    if a.jobs < 1:
        p.error("--jobs must be >= 1")
    if a.backend == "local" and (a.partition or a.time):
        p.error("--partition and --time are for --backend slurm")
    if a.ranks and a.load not in (None, "dem"):
        p.error(f"--ranks runs the coupled DEM on MPI ranks: it needs --load dem (or the config's), not --load {a.load}")
    return a


def options(a):
    """What a case's result depends on besides case.yaml (a change reruns the case)."""
    o = {"load": a.load, "duration": a.duration}
    if getattr(a, "ranks", None):  # only when given: the cases of a sweep made before the option keep their results
        o["ranks"] = a.ranks
    return o


def load_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def is_complete(case_dir, text, opts):
    st = load_json(os.path.join(case_dir, "status.json"))
    if not st or st.get("status") != "ok" or st.get("options") != opts:
        return False
    try:
        same = open(os.path.join(case_dir, "case.yaml")).read() == text
    except OSError:
        return False
    return same and load_json(os.path.join(case_dir, "summary.json")) is not None


def error_line(log_path, rc):
    """Why a run failed: its last error line (ROS's prefixes removed), else the nodes' last word, else the log's
    last line, else the exit status."""
    try:
        lines = [re.sub(r"\x1b\[[0-9;]*m", "", x).strip() for x in open(log_path, errors="replace").read().splitlines()]
    except OSError:
        lines = []
    lines = [x for x in lines if x]
    for pattern in (r"error|what\(\)", r"^(mbd|dem)_node:", r"."):
        hit = next((x for x in reversed(lines) if re.search(pattern, x, re.I)), None)
        if hit:
            hit = re.sub(r"^\[\s*(ERROR|FATAL|WARN)\]\s*\[[0-9.]+\]:\s*", "", hit)
            return hit.replace("[crusher] error: ", "")[:300]
    return f"exit status {rc}, run.log empty"


# Running cases: Popen objects, each the leader of its own process group (stopped together on Ctrl-C).
running = {}


class MasterPool:
    """One ROS master per local worker, kept for the whole sweep: a case's `crusher run` uses a free one
    (CRUSHER_SHARED_MASTER=1) instead of starting its own (rosmaster takes 1-5 s to answer on a busy machine)."""

    def __init__(self, n, log_dir):
        import queue
        import socket
        import xmlrpc.client
        self.procs, self.free = [], queue.Queue()
        env = dict(os.environ, ROS_IP="127.0.0.1")
        env.setdefault("ROS_LOG_DIR", log_dir)
        env.pop("ROS_HOSTNAME", None)
        for _ in range(n):
            s = socket.socket()
            s.bind(("127.0.0.1", 0))
            port = s.getsockname()[1]
            s.close()
            self.procs.append(subprocess.Popen(["rosmaster", "--core", "-p", str(port)], stdout=subprocess.DEVNULL,
                                               stderr=subprocess.DEVNULL, env=env, start_new_session=True))
            uri = f"http://127.0.0.1:{port}/"
            deadline = time.time() + 60
            while True:
                try:
                    xmlrpc.client.ServerProxy(uri).getSystemState("/sweep")
                    break
                except OSError:
                    if time.time() > deadline or self.procs[-1].poll() is not None:
                        self.close()
                        raise SweepError(f"a ROS master for the sweep's workers did not start on port {port}")
                    time.sleep(0.05)
            self.free.put(uri)

    def close(self):
        for p in self.procs:
            if p.poll() is None:
                p.terminate()
        for p in self.procs:
            try:
                p.wait(timeout=5)
            except subprocess.TimeoutExpired:
                p.kill()


masters = None  # MasterPool of the local backend


def run_case(case_dir, opts, keep_bag):
    """One case as `crusher run` (the ROS environment is the caller's); writes status.json, returns it."""
    for f in ("summary.json", "status.json", "run.bag"):
        if os.path.exists(os.path.join(case_dir, f)):
            os.remove(os.path.join(case_dir, f))
    cmd = [CRUSHER, "run", os.path.join(case_dir, "case.yaml"), "--out", case_dir, "--force"]  # the sweep's own folder
    if opts["load"]:
        cmd += ["--load", opts["load"]]
    if opts["duration"]:
        cmd += ["--duration", repr(opts["duration"])]
    if opts.get("ranks"):
        cmd += ["--ranks", str(opts["ranks"])]
    env = dict(os.environ, CRUSHER_NO_BUILD="1", CRUSHER_RUN_PLOTS="0")  # built once by the sweep; no plots per case
    if not keep_bag:
        env["CRUSHER_RUN_BAG"] = "0"  # its bags are deleted below: not joined first (seconds per case)
    uri = masters.free.get() if masters else None
    if uri:
        env.update(ROS_MASTER_URI=uri, CRUSHER_SHARED_MASTER="1")
    t0 = time.time()
    log_path = os.path.join(case_dir, "run.log")
    try:
        with open(log_path, "w") as log:
            proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, env=env, start_new_session=True)
            running[case_dir] = proc
            rc = proc.wait()
            running.pop(case_dir, None)
    finally:
        if uri:
            masters.free.put(uri)
    ok = rc == 0 and load_json(os.path.join(case_dir, "summary.json")) is not None
    status = "ok" if ok else ("interrupted" if rc in (-2, 130, -15, 143) else error_line(log_path, rc))
    if not keep_bag:
        for f in os.listdir(case_dir):
            if f.endswith(".bag"):
                os.remove(os.path.join(case_dir, f))
    st = {"status": status, "rc": rc, "case_wall_s": round(time.time() - t0, 3), "options": opts}
    with open(os.path.join(case_dir, "status.json"), "w") as f:
        json.dump(st, f)
    return st


def stop_running():
    """Ctrl-C: each running case's process group gets SIGINT (the nodes close their bags), then SIGKILL."""
    for proc in list(running.values()):
        try:
            os.killpg(proc.pid, signal.SIGINT)
        except ProcessLookupError:
            pass
    deadline = time.time() + 10
    for proc in list(running.values()):
        try:
            proc.wait(timeout=max(0.1, deadline - time.time()))
        except subprocess.TimeoutExpired:
            try:
                os.killpg(proc.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass


def row(case, keys, values, case_dir):
    """One sweep.csv row (a dict) from the case's summary.json and status.json."""
    r = {k: sweep_cases.fmt(values[k]) for k in keys}
    st = load_json(os.path.join(case_dir, "status.json"))
    s = load_json(os.path.join(case_dir, "summary.json")) if st and st["status"] == "ok" else None
    for col, path in COLUMNS:
        v = s
        for k in path.split("."):
            v = v.get(k) if isinstance(v, dict) else None
        r[col] = "" if v is None else f"{v:.8g}"
    if st and not s:
        r["wall_s"] = f"{st['case_wall_s']:.3g}"
    r["status"] = st["status"] if st else "pending"
    r["case"] = case
    return r


def write_csv(path, keys, rows):
    import csv
    tmp = path + ".tmp"
    with open(tmp, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys + [c for c, _ in COLUMNS] + ["status", "case"])
        w.writeheader()
        w.writerows(rows)
    os.replace(tmp, path)


def hm(seconds):
    m = int(round(seconds / 60))
    return "< 1 min" if seconds < 60 else f"{m // 60} h {m % 60:02d} min"


class Progress:
    def __init__(self, total, done):
        self.total, self.done, self.t0, self.ran = total, done, time.time(), 0

    def case(self, name, st):
        self.done += 1
        self.ran += 1
        el = time.time() - self.t0
        eta = el / self.ran * (self.total - self.done)
        state = "ok" if st["status"] == "ok" else f"FAILED: {st['status']}"
        print(f"[sweep] {self.done}/{self.total} {name}: {state} ({st['case_wall_s']:.1f} s); "
              f"elapsed {hm(el)}, ETA {hm(eta) if self.done < self.total else 'done'}", flush=True)


def run_local(todo, a, on_done):
    from concurrent.futures import ThreadPoolExecutor, as_completed
    global masters
    opts = options(a)
    masters = MasterPool(min(a.jobs, len(todo)), os.path.join(os.path.abspath(a.out), "ros_log")) if todo else None
    try:
        with ThreadPoolExecutor(max_workers=a.jobs) as ex:
            futures = {ex.submit(run_case, d, opts, a.bag): (name, d) for name, d in todo}
            try:
                for fut in as_completed(futures):
                    on_done(*futures[fut], fut.result())
            except KeyboardInterrupt:
                ex.shutdown(wait=False, cancel_futures=True)
                stop_running()
                raise
    finally:
        if masters:
            masters.close()
            masters = None


def main(argv):
    a = parse_args(argv)
    if not os.path.isfile(a.config):
        raise SweepError(f"config '{a.config}' not found")
    config = sweep_cases.config_yaml.load(a.config)
    vary = sweep_cases.parse_vary(a.vary, config)
    keys = [k for k, _ in vary]
    cases = sweep_cases.grid(vary)
    out = os.path.abspath(a.out)
    os.makedirs(os.path.join(out, "cases"), exist_ok=True)
    opts, todo, dirs = options(a), [], {}
    for name, varied in cases:
        d = dirs[name] = os.path.join(out, "cases", name)
        os.makedirs(d, exist_ok=True)
        text = sweep_cases.case_text(*sweep_cases.case_config(a.config, config, varied))
        if not is_complete(d, text, opts):
            if os.path.exists(os.path.join(d, "status.json")):
                os.remove(os.path.join(d, "status.json"))
            with open(os.path.join(d, "case.yaml"), "w") as f:
                f.write(text)
            todo.append((name, d))
    csv_path = os.path.join(out, "sweep.csv")

    def rewrite():
        write_csv(csv_path, keys, [row(n, keys, v, dirs[n]) for n, v in cases])

    rewrite()
    print(f"[sweep] {len(cases)} cases ({' x '.join(f'{len(v)} {k}' for k, v in vary)}), "
          f"{len(cases) - len(todo)} already done, {len(todo)} to run ({a.backend}"
          f"{', %d at once' % a.jobs if a.backend == 'local' else ''}) -> {out}", flush=True)
    progress = Progress(len(cases), len(cases) - len(todo))

    def on_done(name, d, st):
        progress.case(name, st)
        rewrite()

    try:
        if a.backend == "local":
            run_local(todo, a, on_done)
        elif todo:
            import sweep_slurm
            sweep_slurm.run(todo, a, options(a), on_done, out)
    except KeyboardInterrupt:
        rewrite()
        print(f"\n[sweep] interrupted: {progress.done} of {len(cases)} cases done; {csv_path} holds them; "
              "the same command resumes", flush=True)
        return 130
    rewrite()
    rows = [row(n, keys, v, dirs[n]) for n, v in cases]
    failed = [(r["case"], r["status"]) for r in rows if r["status"] != "ok"]
    print(f"[sweep] wrote {csv_path}: {len(rows) - len(failed)} of {len(rows)} cases ok")
    if not a.no_plots and len(failed) < len(rows):
        import plot_sweep
        plot_sweep.report(out, keys)
    for name, err in failed:
        print(f"[sweep] FAILED {name}: {err}")
    return 1 if failed else 0


def run_case_main(argv):
    """`sweep.py --run-case CASEDIR [--load L] [--duration S] [--ranks N] [--bag]`: one case (the Slurm job's command)."""
    p = argparse.ArgumentParser(prog="sweep.py --run-case")
    p.add_argument("case_dir")
    p.add_argument("--load")
    p.add_argument("--duration", type=float)
    p.add_argument("--ranks", type=int)
    p.add_argument("--bag", action="store_true")
    a = p.parse_args(argv)
    try:
        st = run_case(os.path.abspath(a.case_dir), options(a), a.bag)
    except KeyboardInterrupt:  # scancel: the case's processes go too
        stop_running()
        raise
    print(json.dumps(st))
    return 0 if st["status"] == "ok" else 1


if __name__ == "__main__":
    signal.signal(signal.SIGTERM, signal.default_int_handler)  # a kill stops the sweep as Ctrl-C does
    try:
        if sys.argv[1:2] == ["--run-case"]:
            sys.exit(run_case_main(sys.argv[2:]))
        sys.exit(main(sys.argv[1:]))
    except (SweepError, RuntimeError) as e:
        sys.exit(f"[sweep] error: {e}")
    except KeyboardInterrupt:
        sys.exit(130)
