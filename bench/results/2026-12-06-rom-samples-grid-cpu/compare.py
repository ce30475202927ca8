import re, statistics as S, sys, os
folder = os.path.dirname(os.path.abspath(__file__))
# python3 compare.py: base against 37a317c (runs 1-4); python3 compare.py 825de12: base against 825de12 (runs 1-2).
new = sys.argv[1] if len(sys.argv) > 1 else ''
runs = [1, 2] if new else [1, 2, 3, 4]
rows={}
for w in ['base','head']:
  for i in runs:
    prefix = f'rom-cost-{new}-' if new else 'rom-cost-'
    for line in open(f'{folder}/{prefix}{w}-{i}-output.txt'):
      m=re.match(r'\s+(\S+): .*ms per substep by stage: (.*); host traffic per substep: (\d+) allocations, (\d+) uploads, (\d+) downloads',line)
      if m:
        st=dict((k,float(v)) for k,v in re.findall(r'(\w+) ([\d.e+-]+)',m.group(2)))
        rows.setdefault(m.group(1),{}).setdefault(w,[]).append((st,int(m.group(5))))
      m=re.match(r'rom-cost (\S+)\s+cpu\s+2t\s+n=\d+\s+median (\S+) s',line)
      if m: rows.setdefault(m.group(1),{}).setdefault(w+'_t',[]).append(float(m.group(2))*1e3)
print("| case | ms per substep, base → new (median of the runs' medians) | grid_build ms | p2g ms | grid_update ms | downloads |")
print("|---|---|---|---|---|---|")
for case,d in rows.items():
  if 'base' not in d:
    print(f"| {case} | {S.median(d['base_t']):.2f} → {S.median(d['head_t']):.2f} | | | | |"); continue
  med=lambda w,k: S.median([s[0][k] for s in d[w]])
  print(f"| {case} | {S.median(d['base_t']):.2f} → {S.median(d['head_t']):.2f} | {med('base','grid_build'):.3f} → {med('head','grid_build'):.3f} | {med('base','p2g'):.2f} → {med('head','p2g'):.2f} | {med('base','grid_update'):.3f} → {med('head','grid_update'):.3f} | {d['base'][0][1]} → {d['head'][0][1]} |")
