#!/usr/bin/env python3
"""Per scene of a run's results.json: the fastest ok configuration under 1 % and 5 % (the
verdict metric: in-scatter headline; no-scatter is the floor, not a contender), and its GPU
median as a multiple of three floors:

- paired: the record's own paired floor (`run --paired-floor`; what `scatterbench frontier`
  and the report use);
- record: the scene's no-scatter record (what they use without --paired-floor);
- median: the median of every paired floor timed on the scene (one number per scene, robust to
  a single floor's luck; not what the tools use).

Then, per budget and basis, how many scenes' winners are within 2x the floor; and per scene the
spread of its paired floors (the same work timed once per record): p10 and p90 of their GPU
medians.

    python3 ratios.py RUN/results.json
"""
import collections
import json
import statistics
import sys

BUDGETS = (0.01, 0.05)
AFFORDABLE = 2.0


def gpu(t):
    return t["gpu_ms"]["median"] if t and t.get("gpu_ms") else None


def main(path):
    records = json.load(open(path))["records"]
    by_scene = collections.defaultdict(list)
    for r in records:
        if r["status"] == "ok":
            by_scene[r["scene"]].append(r)
    within = collections.Counter()
    for budget in BUDGETS:
        print(f"under {budget:.0%}:")
        for scene, ok in by_scene.items():
            floor_records = [gpu(r["timing"]) for r in ok if r["method"] == "no-scatter"]
            paired = [gpu(r["timing"].get("floor")) for r in ok]
            paired = [p for p in paired if p]
            floors_of = {
                "record": floor_records[0] if floor_records else None,
                "median": statistics.median(paired) if paired else None,
            }
            under = [
                r
                for r in ok
                if r["method"] != "no-scatter"
                and r["errors"]["inscatter"]["headline"] <= budget
            ]
            if not under:
                print(f"  {scene}: none")
                continue
            w = min(under, key=lambda r: gpu(r["timing"]))
            t = gpu(w["timing"])
            floors_of["paired"] = gpu(w["timing"].get("floor"))
            cells = []
            for basis in ("paired", "record", "median"):
                f = floors_of[basis]
                ratio = t / f if f else None
                if ratio is not None and ratio <= AFFORDABLE:
                    within[(budget, basis)] += 1
                cells.append(f"{basis} {ratio:.2f}x" if ratio else f"{basis} -")
            error = w["errors"]["inscatter"]["headline"] * 100
            print(f"  {scene}: {w['method']} {t:.1f} ms, {error:.3f} % | " + ", ".join(cells))
    for (budget, basis), n in sorted(within.items()):
        print(f"under {budget:.0%}, within {AFFORDABLE}x the {basis} floor: {n} of {len(by_scene)}")
    print("paired floors per scene: count, p10-p90 GPU ms")
    for scene, ok in by_scene.items():
        paired = sorted(p for p in (gpu(r["timing"].get("floor")) for r in ok) if p)
        if paired:
            q = lambda f: paired[int(f * (len(paired) - 1))]
            print(f"  {scene}: {len(paired)}, {q(0.1):.1f}-{q(0.9):.1f}")


if __name__ == "__main__":
    main(sys.argv[1])
