#!/usr/bin/env python3
"""Per scene of one or more confirm runs (paired floors matched to each record's shadow-map
settings, ARCHITECTURE 4.5): the fastest configuration under 1 % by its paired floor ratio,
over every configuration, and over those whose paired floor ran at its defaults
(shadow_map 1024: a floor no knob of the method moved). One Markdown row per scene,
"all / defaults-floor" per run, the first run's two winners named; then, per run, how many
scenes each reads within 2x.

    python3 matched.py A/results.json [B/results.json ...]
"""
import collections
import json
import sys

def rows(path):
    out=collections.defaultdict(list)
    for r in json.load(open(path))["records"]:
        if r["status"]!="ok" or r["method"]=="no-scatter": continue
        t=r["timing"];f=t.get("floor")
        if not f: continue
        fsm=f.get("params",{}).get("shadow_map",1024)
        out[r["scene"]].append((t["gpu_ms"]["median"]/f["gpu_ms"]["median"], r["errors"]["inscatter"]["headline"], r["method"], r["params"], fsm))
    return out
def name(m,p):
    keep={k:v for k,v in p.items() if k in("scale","samples","shadow_map","columns","slices","resolve","fit","table","falloff","silhouettes","spot_integral","panels")}
    return m+" "+",".join(f"{k}={v}" for k,v in keep.items())
runs=[rows(p) for p in sys.argv[1:]]
cnt=collections.Counter()
for sc in runs[0]:
    line=[]
    for i,R in enumerate(runs):
        c=[x for x in R[sc] if x[1]<=0.01]
        a=min(c,key=lambda x:x[0]) if c else None
        d=[x for x in c if x[4]==1024]
        b=min(d,key=lambda x:x[0]) if d else None
        if a and a[0]<=2: cnt[(i,'all')]+=1
        if b and b[0]<=2: cnt[(i,'default')]+=1
        line.append(f"{a[0]:.2f} / {b[0]:.2f}" if a and b else "-")
        if i==0: w=(name(a[2],a[3]), name(b[2],b[3]) if b else "-")
    print(f"| {sc} | {' | '.join(line)} | {w[0]} | {w[1]} |")
print(dict(cnt))
