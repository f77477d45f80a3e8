#!/usr/bin/env python3
"""A run config as the nodes read it (core::ConfigNode::load_file): a top-level `base: FILE` (relative to the file)
is loaded first and the file's keys laid over it; mappings merge key by key, lists and values replace.
Usage as a module: config_yaml.load(path) -> dict. As a command: config_yaml.py CONFIG [KEY.PATH] prints the
merged config as JSON, or one value (e.g. run.load)."""
import json
import os
import sys

import yaml


def _merged(base, over):
    if not isinstance(base, dict) or not isinstance(over, dict):
        return over
    out = dict(base)
    for k, v in over.items():
        out[k] = _merged(out[k], v) if k in out else v
    return out


def load(path, _depth=0):
    with open(path) as f:
        c = yaml.safe_load(f) or {}
    if not isinstance(c, dict):
        raise ValueError(f"config {path}: the top level must be a mapping of keys")
    base = c.pop("base", None)
    if base is None:
        return c
    if _depth >= 8:
        raise ValueError(f"config {path}: 'base' chains deeper than 8 files (a cycle?)")
    if not os.path.isabs(base):
        base = os.path.join(os.path.dirname(path), base)
    return _merged(load(base, _depth + 1), c)


def value(config, dotted, default=None):
    v = config
    for k in dotted.split("."):
        if not isinstance(v, dict) or k not in v:
            return default
        v = v[k]
    return v


if __name__ == "__main__":
    c = load(sys.argv[1])
    print(json.dumps(value(c, sys.argv[2]) if len(sys.argv) > 2 else c))
