#!/usr/bin/env python3
"""Builds the "Latest run, the tail" table of bench/results/README.md from broadphase_bench
reports (bench/results/broadphase*.md): per configuration, ours and the best peer from the
report's headline, ours' p99 / median (wall clock and thread CPU time; in CPU time also without
the first cycle of each round-robin block, which runs after the other peers with cold caches),
and the other rows of ours measured in the same run: every run's end at once (spread_updates 0),
no steady lead (steady_lead false) and lead 16 (coast_updates 16). Every row of ours is matched
by its own name: a row whose name the script does not know is an error, never taken for ours.
Usage: python3 bench/tail_table.py REPORT.md [REPORT.md ...] > table.md"""
import re
import sys


# The rows of ours in a report, by their exact names (broadphase_bench.cpp's peers).
ROWS = {
    'ours (SweepAndPrune)': 'ours',
    "ours, run's end at once (spread_updates 0)": 'once',
    'ours, no steady lead (steady_lead false)': 'nosteady',
    'ours, lead 16 (coast_updates 16)': 'lead16',
    'ours as in the baseline (WP_BENCH_BASELINE)': 'baseline',
}


def parse(path):
    text = open(path).read()
    head = {}
    sect = text[text.index('## Headline'):text.index('## Targets')]
    for line in sect.splitlines():
        if line.startswith('| ') and not line.startswith('| scene') and not line.startswith('|---'):
            cells = [c.strip() for c in line.strip('|').split('|')]
            head[cells[0]] = cells
    rows = {}
    body = text[text.index('## Every configuration'):] if '## Every configuration' in text else text
    cur = None
    for line in body.splitlines():
        m = re.match(r'^### (.*)$', line)
        if m:
            cur = m.group(1).strip()
            continue
        if line.startswith('| ours') and cur:
            cells = [c.strip() for c in line.strip('|').split('|')]
            cpu = re.search(r'CPU time: median ([\d.]+), p99 ([\d.]+), ([\d.]+)×', cells[-1])
            warm = re.search(r"without each block's first cycle: p99 ([\d.]+), ([\d.]+)×", cells[-1])
            key = ROWS.get(cells[0])
            if key is None:
                sys.exit(f'tail_table.py: {path}: unknown row of ours: {cells[0]!r}')
            rows.setdefault(cur, {})[key] = dict(median=float(cells[1]), p99=float(cells[2]),
                                                 mean=float(cells[3]),
                                                 cpu=cpu.groups() if cpu else None,
                                                 warm=warm.groups() if warm else None)
    return head, rows


def fmt(us):
    return f'{us / 1000:.3g} ms' if us >= 1000 else f'{us:.3g} µs'


def short(name):
    n = re.search(r'N = (\d+)', name)
    count = int(n.group(1)) if n else None
    ns = f'{count:,}'.replace(',', ' ') if count else ''
    if name.startswith('uniform'):
        pct = re.search(r'motion (\d+) %', name).group(1)
        return f'uniform, {pct} %, N = {ns}'
    if name.startswith('jitter'):
        pct = re.search(r'jitter \+-([\d.]+) %', name).group(1)
        return f'jitter ±{pct} %, N = {ns}'
    if name.startswith('walkers'):
        return f"walkers' swept bounds, N = {ns}"
    if name.startswith('warehouse'):
        return f'warehouse, 1 % churn, N = {ns}'
    return name


def other(row):
    if not row:
        return '–'
    ratio = row['cpu'][2] + '×' if row['cpu'] else '–'
    return f"{fmt(row['median'])}, {fmt(row['mean'])}, {fmt(row['p99'])}, {ratio}"


out = []
for path in sys.argv[1:]:
    head, rows = parse(path)
    for cfg, r in rows.items():
        if 'ours' not in r:
            continue
        s = short(cfg)
        h = None
        for k, v in head.items():
            if k == s or k.replace(' ', '') == s.replace(' ', ''):
                h = v
        o = r['ours']
        best = f'{h[2]} | {h[3]} | {h[4]} | {h[5]}' if h else '– | – | – | –'
        cpu = o['cpu']
        cpu_s = f'{fmt(float(cpu[0]))}, {fmt(float(cpu[1]))}, **{cpu[2]}×**' if cpu else '–'
        warm = o.get('warm')
        warm_s = f'{fmt(float(warm[0]))}, {warm[1]}×' if warm else '–'
        out.append(f"| {s} | {fmt(o['median'])} | {best} | {fmt(o['p99'])} | "
                   f"{o['p99'] / o['median']:.1f}× | {cpu_s} | {warm_s} | {other(r.get('once'))} | "
                   f"{other(r.get('nosteady'))} | {other(r.get('lead16'))} |")
print('| scene | ours median | best peer | its median | ratio | means: ours, best peer, ratio | '
      'ours p99 | p99 / median | ours in CPU time: median, p99, p99 / median | '
      "the same without each round-robin block's first cycle: p99, p99 / median | "
      "run's end at once (same run): median, mean, p99, p99 / median in CPU time | "
      'no steady lead (same run): median, mean, p99, p99 / median in CPU time | '
      'lead 16 (same run): median, mean, p99, p99 / median in CPU time |')
print('|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|')
print('\n'.join(out))
