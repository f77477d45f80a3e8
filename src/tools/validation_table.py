#!/usr/bin/env python3
"""Markdown table of validation.json (src/tools/validate.cpp) for the README: plant, the paper's simulation and
ours at 400 and 600 rpm, our error and the paper's; '*' marks values calibrated at 400 rpm.
Usage: validation_table.py validation.json"""
import json
import sys


def cell(v, nd=2):
    return "-" if v is None else f"{v:.{nd}f}"


def err(v):
    return "-" if v is None else f"{100 * v:+.0f} %"


def main(path):
    v = json.load(open(path))
    print("| quantity | plant 400 | paper 400 | ours 400 | ours err | paper err | plant 600 | paper 600 | ours 600 "
          "| ours err | paper err |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in v["rows"]:
        star = "*" if r["calibrated400"] else ""
        nd = 1 if r["quantity"] == "wall_s" else 2
        print(f"| {r['label']} | {cell(r['exp400'])} | {cell(r['sim400'])} | {cell(r['ours400'], nd)}{star} | "
              f"{err(r['error400'])} | {err(r['paper_error400'])} | {cell(r['exp600'])} | {cell(r['sim600'])} | "
              f"{cell(r['ours600'], nd)} | {err(r['error600'])} | {err(r['paper_error600'])} |")
    t = v["trends"]
    yn = {True: "yes", False: "no", None: "n/a"}
    print(f"\nProduct index at 400 rpm (over 80 % passing 12 mm, under 3 % passing 1 mm): "
          f"{yn[v['product_index_400']]}. Trends from 400 to 600 rpm: power up {yn[t['power_up']]}, throughput down "
          f"{yn[t['throughput_down']]}, product finer {yn[t['product_finer']]}.")


if __name__ == "__main__":
    main(sys.argv[1])
