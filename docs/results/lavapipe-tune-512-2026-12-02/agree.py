#!/usr/bin/env python3
"""Agreement of two `scatterbench tune` runs of the same command (issue 47).

Per scene and budget (a cell): the winner of each run; where a run's intervals separate its
winner from its runner-up (no tie), whether the other run crowned the same method and the same
configuration; and whether each run's winner interval contains the other run's winner ratio.

    python3 agree.py A/tune.json B/tune.json
"""
import json
import sys


def cells(path):
    t = json.load(open(path))
    out = {}
    for s in t["scenes"]:
        for v in s["verdicts"]:
            w = v["winner"]
            c = s["candidates"][w] if w is not None else None
            out[(s["scene"], v["budget"])] = (c, v["separable"] and not v["tie"])
    return t, out


def main(a_path, b_path):
    ta, a = cells(a_path)
    tb, b = cells(b_path)
    rows, sep, same_m, same_c, contains, n = [], 0, 0, 0, 0, 0
    for key in a:
        (ca, sa), (cb, sb) = a[key], b.get(key, (None, False))
        if ca is None or cb is None:
            rows.append((key, "—" if ca is None else ca["method"], "—" if cb is None else cb["method"], "", ""))
            continue
        ra, rb = ca["ratio"], cb["ratio"]
        inside = lambda r, x: r["low"] <= x <= (r["high"] if r["high"] is not None else float("inf"))
        both = inside(ra, rb["estimate"]) and inside(rb, ra["estimate"])
        n += 1
        contains += inside(ra, rb["estimate"]) + inside(rb, ra["estimate"])
        agree = ""
        if sa or sb:
            sep += 1
            m = ca["method"] == cb["method"]
            c = m and ca["params"] == cb["params"]
            same_m += m
            same_c += c
            agree = "same config" if c else ("same method" if m else "DIFFERENT")
        rows.append((key, f'{ca["method"]} {ca["knobs"]} {ra["estimate"]:.2f} [{ra["low"]:.2f}, {ra["high"] or float("inf"):.2f}]',
                     f'{cb["method"]} {cb["knobs"]} {rb["estimate"]:.2f} [{rb["low"]:.2f}, {rb["high"] or float("inf"):.2f}]',
                     agree, "both contain" if both else ""))
    print("| scene | budget | A | B | separated: agree? | intervals |")
    print("|---|---|---|---|---|---|")
    for (scene, budget), wa, wb, agree, both in rows:
        print(f"| {scene} | {budget:.0%} | {wa} | {wb} | {agree} | {both} |")
    print()
    print(f"cells with a winner in both: {n}; separated in either run: {sep}; of those the same method: "
          f"{same_m}, the same configuration: {same_c}")
    print(f"a winner's interval contains the other run's ratio: {contains} of {2 * n} "
          f"({100 * contains / max(1, 2 * n):.0f} %)")
    for t, name in [(ta, "A"), (tb, "B")]:
        print(f"{name}: wall {t['wall_s']:.0f} s; " + "; ".join(
            f"≤ {c['budget']:.0%}: {c['k']} of {c['n']} within {c['limit']}× ({c['low']}–{c['high']})" for c in t["summary"]))


if __name__ == "__main__":
    main(*sys.argv[1:3])
