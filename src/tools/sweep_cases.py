#!/usr/bin/env python3
"""The cases of a sweep: the grid of --vary values and each case's config (crusher sweep; sweep.py).

A case config is `base: /abs/CONFIG` plus the varied keys and the values that follow them (derived):
- a body's inertia scales with its mass (inertia ~ mass at fixed shape) unless an inertia component is varied;
- with the drive speed varied, the mechanism step is the largest that divides coupling.dt_s into whole steps
  and keeps the drive rotation per step w dt at or below the base config's (0.042 rad in gyp1200_400rpm.yaml).
"""
import math
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts"))
import config_yaml  # noqa: E402  (the config as the nodes read it: crusher config --json)
import yaml  # noqa: E402

SPEED = "mbd.drive.speed_rpm"
TIME_STEP = "mbd.time_step_s"
COUPLING_DT = "coupling.dt_s"
COUPLING_DT_DEFAULT = 1e-3  # core::CouplingOptions::dt_s


class SweepError(ValueError):
    pass


_KEY = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*(?:\.[A-Za-z_][A-Za-z0-9_]*)*)(?:\[(\d+)\])?$")


def parse_key(key):
    """'a.b.c' or 'a.b.c[i]' (a list element) -> (['a', 'b', 'c'], i or None)."""
    m = _KEY.match(key)
    if not m:
        raise SweepError(f"--vary: key '{key}' is not a dotted config path (e.g. {SPEED} or mbd.absorbers.stiffness_N_per_mm[0])")
    return m.group(1).split("."), (int(m.group(2)) if m.group(2) is not None else None)


def get(config, key):
    path, index = parse_key(key)
    v = config_yaml.value(config, ".".join(path))
    if index is not None:
        v = v[index] if isinstance(v, list) and index < len(v) else None
    return v


def _set(tree, key, value):
    """Sets KEY (a path, or a list element whose list is already in tree) in the nested dict tree."""
    path, index = parse_key(key)
    node = tree
    for k in path[:-1]:
        node = node.setdefault(k, {})
    if index is None:
        node[path[-1]] = value
    else:
        node[path[-1]][index] = value


def values(spec):
    """'FROM:TO:STEP' (TO included when the steps reach it) or 'V1,V2,...' -> list of floats."""
    try:
        if ":" in spec:
            a, b, s = (float(x) for x in spec.split(":"))
            if s <= 0 or b < a:
                raise SweepError(f"--vary: range '{spec}' needs FROM <= TO and STEP > 0")
            n = int(math.floor((b - a) / s + 1e-9)) + 1
            return [float(f"{a + i * s:.12g}") for i in range(n)]
        return [float(x) for x in spec.split(",")]
    except ValueError as e:
        if isinstance(e, SweepError):
            raise
        raise SweepError(f"--vary: '{spec}' is neither FROM:TO:STEP nor V1,V2,... of numbers") from None


def parse_vary(items, config):
    """['KEY=SPEC', ...] -> [(key, [values])], each key a number in the config."""
    if not 1 <= len(items) <= 2:
        raise SweepError("give one or two --vary KEY=FROM:TO:STEP")
    out = []
    for item in items:
        key, eq, spec = item.partition("=")
        if not eq:
            raise SweepError(f"--vary '{item}': expected KEY=FROM:TO:STEP")
        v = get(config, key)
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            what = ("not in the config" if v is None else "a section, not a number" if isinstance(v, dict)
                    else f"not a number: {v!r}")
            raise SweepError(f"--vary: '{key}' is {what}"
                             " (any numeric key of the merged config; list elements as KEY[i])")
        vals = values(spec)
        if isinstance(v, int) and all(x.is_integer() for x in vals):  # an integer key (e.g. flow.bands) stays one
            vals = [int(x) for x in vals]
        out.append((key, vals))
    if len(out) == 2 and out[0][0] == out[1][0]:
        raise SweepError(f"--vary: '{out[0][0]}' given twice")
    return out


def short_names(keys):
    """The shortest dotted tails that tell the keys apart: mbd.drive.speed_rpm -> speed_rpm."""
    for n in range(1, 10):
        names = [".".join(parse_key(k)[0][-n:]) + (f"{parse_key(k)[1]}" if parse_key(k)[1] is not None else "")
                 for k in keys]
        if len(set(names)) == len(names):
            return [s.replace(".", "_") for s in names]
    return [k.replace(".", "_") for k in keys]


def fmt(v):
    return f"{v:.10g}"


def grid(vary):
    """[(name, {key: value})] over the product of the varied values, the first key slowest."""
    keys = [k for k, _ in vary]
    names = short_names(keys)
    cases = [{}]
    for key, vals in vary:
        cases = [dict(c, **{key: v}) for c in cases for v in vals]
    return [("-".join(f"{n}_{fmt(c[k])}" for n, k in zip(names, keys)), c) for c in cases]


def derived(config, varied):
    """The values that follow the varied ones: {key: value}, and one line of explanation per key."""
    out, why = {}, []
    varied_paths = {".".join(parse_key(k)[0]) for k in varied}
    for body, sec in (config.get("mbd") or {}).items():
        if not isinstance(sec, dict):
            continue
        mkey, ikey = f"mbd.{body}.mass_kg", f"mbd.{body}.inertia_kg_m2"
        if mkey in varied and ikey not in varied_paths and isinstance(sec.get("inertia_kg_m2"), list):
            f = varied[mkey] / sec["mass_kg"]
            out[ikey] = [float(f"{i * f:.10g}") for i in sec["inertia_kg_m2"]]
            why.append(f"{ikey} = base x {fmt(f)} (inertia ~ mass at fixed shape)")
    if SPEED in varied and TIME_STEP not in varied_paths:
        rpm0, dt0 = get(config, SPEED), get(config, TIME_STEP)
        dc = get(config, COUPLING_DT) or COUPLING_DT_DEFAULT
        limit = rpm0 * math.pi / 30 * dt0  # the base config's drive rotation per step
        w = varied[SPEED] * math.pi / 30
        n = max(1, math.ceil(w * dc / limit - 1e-9))
        out[TIME_STEP] = float(f"{dc / n:.10g}")
        why.append(f"{TIME_STEP} = coupling.dt_s / {n} (w dt = {w * dc / n:.4f} rad <= the base's {limit:.4f} rad)")
    return out, why


def case_config(config_path, config, varied):
    """(dict of the case.yaml, its comment lines): base plus varied plus derived values."""
    extra, why = derived(config, varied)
    tree = {"base": os.path.abspath(config_path)}
    for key, v in list(varied.items()) + list(extra.items()):
        path, index = parse_key(key)
        if index is not None and get(tree, ".".join(path)) is None:  # a list element: copy the base list first
            _set(tree, ".".join(path), list(config_yaml.value(config, ".".join(path))))
        _set(tree, key, v)
    lines = ["varied: " + ", ".join(f"{k} = {fmt(v)}" for k, v in varied.items())]
    lines += ["derived: " + w for w in why]
    return tree, lines


def case_text(tree, lines):
    """case.yaml's text: the explanation as comments, then the keys."""
    return "".join(f"# {line}\n" for line in lines) + yaml.safe_dump(tree, sort_keys=False)
