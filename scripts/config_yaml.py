#!/usr/bin/env python3
"""A run config as the nodes read it, through the C++ schema (`crusher config --json`): the `base:` chain applied,
every key validated (unknown, missing, out of range, duplicate keys refused by name), defaults filled in.
The tool is $CRUSHER_CONFIG_TOOL (config_tool) when set, else `scripts/crusher config`.
Usage as a module: config_yaml.load(path) -> dict (ValueError naming the key on a bad config). As a command:
config_yaml.py CONFIG [KEY.PATH ...] prints the config as JSON, or each key's value on its own line (e.g. run.load;
null when not set), read once."""
import json
import os
import subprocess
import sys


def load(path):
    tool = os.environ.get("CRUSHER_CONFIG_TOOL")
    cmd = [tool] if tool else ["bash", os.path.join(os.path.dirname(os.path.abspath(__file__)), "crusher"), "config"]
    r = subprocess.run(cmd + ["--json", path], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        raise ValueError(r.stderr.strip() or f"config {path}: config_tool exited {r.returncode}")
    return json.loads(r.stdout)


def value(config, dotted, default=None):
    v = config
    for k in dotted.split("."):
        if not isinstance(v, dict) or k not in v:
            return default
        v = v[k]
    return v


if __name__ == "__main__":
    try:
        c = load(sys.argv[1])
    except ValueError as e:
        sys.exit(str(e))
    if len(sys.argv) > 2:
        for key in sys.argv[2:]:
            print(json.dumps(value(c, key)))
    else:
        print(json.dumps(c))
