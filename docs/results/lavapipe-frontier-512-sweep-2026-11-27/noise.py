#!/usr/bin/env python3
"""How much two runs of the same configurations disagree: per configuration both runs have
(same scene, method and knobs, ok, with a paired floor), |ln(A/B)| of its floor ratio (GPU
median / paired floor's GPU median), of its own GPU median and of its paired floor's; printed
as the median (and p90 for the ratio) over the configurations, with whether the runs'
floors were interleaved with the records' frames (ARCHITECTURE 4.5).

    python3 noise.py RUN_A/results.json RUN_B/results.json
"""
import json
import math
import statistics
import sys


def load(path):
    out = {}
    for r in json.load(open(path))["records"]:
        if r["status"] != "ok":
            continue
        t = r["timing"]
        floor = t.get("floor")
        key = (r["scene"], r["method"], json.dumps(r["params"], sort_keys=True))
        out[key] = (
            t["gpu_ms"]["median"],
            floor["gpu_ms"]["median"] if floor else None,
            bool(floor and floor.get("interleaved")),
        )
    return out


def nearest_rank(values, p):
    v = sorted(values)
    return v[int(p * (len(v) - 1))]


def main(path_a, path_b):
    a, b = load(path_a), load(path_b)
    ratio, time, floor, interleaved = [], [], [], set()
    for key, (ta, fa, ia) in a.items():
        if key not in b or not fa or not b[key][1]:
            continue
        tb, fb, ib = b[key]
        ratio.append(abs(math.log((ta / fa) / (tb / fb))))
        time.append(abs(math.log(ta / tb)))
        floor.append(abs(math.log(fa / fb)))
        interleaved |= {ia, ib}
    if not ratio:
        sys.exit("no configuration with a paired floor in both runs")
    print(
        f"{len(ratio)} configurations, interleaved {sorted(interleaved)}: median |ln(A/B)| "
        f"of the floor ratio {statistics.median(ratio):.3f} (p90 {nearest_rank(ratio, 0.9):.3f}), "
        f"of the record's time {statistics.median(time):.3f}, "
        f"of its paired floor {statistics.median(floor):.3f}"
    )


if __name__ == "__main__":
    main(*sys.argv[1:3])
