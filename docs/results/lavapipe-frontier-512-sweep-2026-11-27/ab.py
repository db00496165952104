#!/usr/bin/env python3
"""A change's effect on the floor ratios of the same configurations: per scene and method, the
mean of ln(new / old) over its configurations, "old" being the geometric mean of the same
configuration's floor ratio (GPU median / paired floor's GPU median) over the OLD runs; and
how many headlines differ by more than 1e-5 relative (a change meant to keep every image).

    python3 ab.py OLD_A/results.json[,OLD_B/results.json...] NEW/results.json
"""
import collections
import json
import math
import statistics
import sys


def load(path):
    out = {}
    for r in json.load(open(path))["records"]:
        t = r["timing"] or {}
        if r["status"] != "ok" or not t.get("floor"):
            continue
        key = (r["scene"], r["method"], json.dumps(r["params"], sort_keys=True))
        ratio = t["gpu_ms"]["median"] / t["floor"]["gpu_ms"]["median"]
        out[key] = (ratio, r["errors"]["inscatter"]["headline"])
    return out


def main(old_paths, new_path):
    olds = [load(p) for p in old_paths.split(",")]
    new = load(new_path)
    by = collections.defaultdict(list)
    differ = 0
    for key, (ratio, headline) in new.items():
        before = [o[key] for o in olds if key in o]
        if not before:
            continue
        ref = math.exp(statistics.mean(math.log(b[0]) for b in before))
        by[key[:2]].append(math.log(ratio / ref))
        differ += sum(abs(b[1] - headline) > 1e-5 * max(abs(headline), 1e-6) for b in before)
    for (scene, method), v in sorted(by.items()):
        print(f"{scene:20s} {method:30s} n={len(v)} mean ln(new/old) = {statistics.mean(v):+.3f}")
    print(f"headlines differing: {differ}")


if __name__ == "__main__":
    main(*sys.argv[1:3])
