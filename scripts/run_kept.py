#!/usr/bin/python3
"""What a failed or stopped `crusher run` left in its folder, checked rather than assumed (issue 22).

Usage: scripts/run_kept.py DIR

Prints one line: `kept in DIR: ...; not kept: ...`. summary.json counts when it reads as JSON (its `stopped` says
why the run ended early), run.bag when it opens as an indexed bag, a checkpoint when every node of the run wrote
that step (the one `--resume` continues from). Exit status 0 always: this only reports.
"""
import glob
import json
import os
import re
import sys


def summary(d):
    p = os.path.join(d, "summary.json")
    if not os.path.exists(p):
        return None, "summary.json (the node could not write it, or did not get that far)"
    try:
        with open(p) as f:
            s = json.load(f)
    except (OSError, ValueError) as e:
        return None, f"summary.json (it does not read as JSON: {e})"
    t = s.get("simulated_s")
    return "summary.json" + (f" ({t:.3f} s simulated)" if isinstance(t, (int, float)) else ""), None


def bag(d):
    p = os.path.join(d, "run.bag")
    segs = sorted(glob.glob(os.path.join(d, "run.seg*.bag")))
    if not os.path.exists(p):
        if segs:
            n = len(segs)
            return f"{n} bag segment{'s' if n > 1 else ''} run.seg*.bag (not joined into run.bag)", "run.bag"
        return None, "run.bag"
    try:
        import rosbag
        with rosbag.Bag(p) as b:
            n = b.get_message_count()
        return f"run.bag ({n} messages)", None
    except Exception as e:  # unindexed (its node stopped at a write error) or not a bag
        return None, f"a readable run.bag ({type(e).__name__}: {e}; `rosbag reindex` may mend it)"


def checkpoint(d):
    steps = {}
    for p in glob.glob(os.path.join(d, "checkpoint", "*.ckpt")):
        m = re.match(r"(\w+)\.(\d+)\.ckpt$", os.path.basename(p))
        if m:
            steps.setdefault(m.group(1), set()).add(int(m.group(2)))
    if not steps:
        return None, None
    common = set.intersection(*steps.values())
    if not common:
        return None, "a checkpoint written by every node (none in common: --resume cannot continue)"
    return f"checkpoint at step {max(common)} (--resume continues from it)", None


def main():
    d = sys.argv[1]
    kept, lost = [], []
    for k, l in (summary(d), bag(d), checkpoint(d)):
        if k:
            kept.append(k)
        if l:
            lost.append(l)
    line = f"kept in {d}: " + (", ".join(kept) if kept else "nothing of use")
    if lost:
        line += "; not kept: " + ", ".join(lost)
    print(line)


if __name__ == "__main__":
    main()
