#!/usr/bin/env python3
"""crusher sweep --backend slurm: the cases to run as one Slurm job array (sbatch), collected as they finish.
Each array task runs `sweep.py --run-case CASEDIR` (one `crusher run`) on a node; this repository, its build and
DIR must be on a file system the nodes share. Ctrl-C cancels the array (scancel); the same command resumes."""
import json
import os
import subprocess
import time

HERE = os.path.dirname(os.path.abspath(__file__))
POLL_S = float(os.environ.get("CRUSHER_SWEEP_POLL_S", "2"))


def ros_setup():
    """The built workspace's setup.bash (the devel folder ROS put first on CMAKE_PREFIX_PATH)."""
    for p in os.environ.get("CMAKE_PREFIX_PATH", "").split(":"):
        if p and os.path.isfile(os.path.join(p, "setup.bash")):
            return os.path.join(p, "setup.bash")
    raise RuntimeError("no ROS workspace on CMAKE_PREFIX_PATH (run through scripts/crusher sweep)")


def batch_script(sdir, listing, n, a, opts):
    lines = ["#!/bin/bash", "#SBATCH --job-name=crusher-sweep", f"#SBATCH --array=0-{n - 1}",
             f"#SBATCH --cpus-per-task={a.cpus_per_case}", f"#SBATCH --output={sdir}/%A_%a.out"]
    if opts.get("ranks"):  # the case's dem_node ranks (mpirun inside the task's allocation places them)
        lines.append(f"#SBATCH --ntasks={opts['ranks']}")
    if a.partition:
        lines.append(f"#SBATCH --partition={a.partition}")
    if a.time:
        lines.append(f"#SBATCH --time={a.time}")
    args = ""
    if opts["load"]:
        args += f" --load {opts['load']}"
    if opts["duration"]:
        args += f" --duration {opts['duration']!r}"
    if opts.get("ranks"):
        args += f" --ranks {opts['ranks']}"
    if a.bag:
        args += " --bag"
    lines += ["set +u", f"source {ros_setup()}", "set -eu",
              "export OMP_NUM_THREADS=${SLURM_CPUS_PER_TASK:-1}  # dem.threads 0: the case's cores",
              f"case=$(sed -n \"$((SLURM_ARRAY_TASK_ID + 1))p\" {listing})",
              f"exec /usr/bin/python3 {HERE}/sweep.py --run-case \"$case\"{args}"]
    return "\n".join(lines) + "\n"


def slurm(cmd):
    return subprocess.run(cmd, capture_output=True, text=True)


def job_finished(job):
    q = slurm(["squeue", "-h", "-j", job, "-o", "%i"])
    if q.returncode != 0:
        return "Invalid job id" in q.stderr  # gone from the queue; other errors: the controller is busy, ask again
    return q.stdout.strip() == ""


def run(todo, a, opts, on_done, out):
    if not todo:
        return
    sdir = os.path.join(out, "slurm")
    os.makedirs(sdir, exist_ok=True)
    stamp = time.strftime("%Y%m%d-%H%M%S")
    listing = os.path.join(sdir, f"cases-{stamp}.txt")
    with open(listing, "w") as f:
        f.write("".join(d + "\n" for _, d in todo))
    script = os.path.join(sdir, f"array-{stamp}.sh")
    with open(script, "w") as f:
        f.write(batch_script(sdir, listing, len(todo), a, opts))
    sub = slurm(["sbatch", "--parsable", script])
    if sub.returncode != 0:
        raise RuntimeError(f"sbatch {script} failed: {sub.stderr.strip() or sub.stdout.strip()}")
    job = sub.stdout.strip().split(";")[0]
    print(f"[sweep] slurm job array {job}: {len(todo)} tasks (script {script})", flush=True)
    pending = dict(enumerate(todo))
    try:
        while pending:
            finished = job_finished(job)
            for i, (name, d) in list(pending.items()):
                st = _status(d)
                if st is None and finished:  # the task ended without a result: its output says why
                    st = _lost(d, os.path.join(sdir, f"{job}_{i}.out"))
                if st is not None:
                    del pending[i]
                    on_done(name, d, st)
            if pending:
                time.sleep(POLL_S)
    except KeyboardInterrupt:
        slurm(["scancel", job])
        print(f"[sweep] cancelled slurm job {job}", flush=True)
        raise


def _status(d):
    try:
        with open(os.path.join(d, "status.json")) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def _lost(d, out_file):
    try:
        tail = open(out_file, errors="replace").read().strip().splitlines()[-1:]
    except OSError:
        tail = []
    st = {"status": "slurm: the task ended without a result" + (f" ({tail[0][:200]})" if tail else ""),
          "rc": None, "case_wall_s": 0.0, "options": None}
    with open(os.path.join(d, "status.json"), "w") as f:
        json.dump(st, f)
    return st
