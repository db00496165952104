import json,sys
a=json.load(open(sys.argv[1])); b=json.load(open(sys.argv[2]))
def key(r): return (r['scene'],r['method'],json.dumps(r.get('params'),sort_keys=True))
def head(r):
    e=(r.get('errors') or {}).get('inscatter') or {}
    return e.get('headline')
A={key(r):r for r in a['records']}; B={key(r):r for r in b['records']}
same=diff=0; rows=[]
for k in sorted(set(A)|set(B)):
    ra,rb=A.get(k),B.get(k)
    if not ra or not rb: rows.append(("missing",k)); continue
    if ra['status']!=rb['status']: rows.append(("status",k,ra['status'],rb['status'])); continue
    if ra['status']!='ok': continue
    ha,hb=head(ra),head(rb)
    fa,fb=f"{ha:.3g}",f"{hb:.3g}"
    if fa==fb: same+=1
    else:
        diff+=1; ca,cb=ra.get('counters',{}),rb.get('counters',{})
        rows.append(("differ",k[0],k[1],fa,fb,f"frames {ca.get('warmup_frames')}+{ca.get('timed_frames')} vs {cb.get('warmup_frames')}+{cb.get('timed_frames')}"))
print(f"ok records compared: {same+diff}; same to 3 significant digits: {same}; differ: {diff}")
for r in rows: print(*r)
