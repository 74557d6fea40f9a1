#!/usr/bin/env python3
"""compare.py BEFORE AFTER: two captures of capture.sh are the same: every file byte for byte, except
the lab report (report.json, numbers to 1e-9 relative; its HTML, text and plots hold timings and
paths)."""
import json, os, sys, filecmp
a, b = sys.argv[1], sys.argv[2]
bad = 0
def num_eq(x, y, path):
    global bad
    if isinstance(x, dict):
        if set(x) != set(y): print('keys differ', path, set(x) ^ set(y)); bad += 1; return
        for k in x: num_eq(x[k], y[k], path + '/' + k)
    elif isinstance(x, list):
        if len(x) != len(y): print('len differs', path); bad += 1; return
        for i, (p, q) in enumerate(zip(x, y)): num_eq(p, q, '%s[%d]' % (path, i))
    elif isinstance(x, float) and isinstance(y, (int, float)):
        if abs(x - y) > 1e-9 * max(1.0, abs(x)): print('value', path, x, y); bad += 1
    elif isinstance(x, str) and path.endswith(('seconds', 'time_s')):
        pass
    elif x != y and not path.endswith('_s'):
        print('differs', path, str(x)[:80], str(y)[:80]); bad += 1
for root, dirs, files in os.walk(a):
    for f in files:
        p = os.path.join(root, f); q = os.path.join(b, os.path.relpath(p, a))
        if not os.path.exists(q): print('missing', q); bad += 1; continue
        if f == 'report.json':
            num_eq(json.load(open(p)), json.load(open(q)), f)
        elif f.endswith(('.html', '.txt', '.png')) and 'lab' in p:
            continue  # timings, paths, plots: compared through report.json
        elif not filecmp.cmp(p, q, shallow=False):
            print('bytes differ', os.path.relpath(p, a)); bad += 1
print('differences:', bad)
sys.exit(1 if bad else 0)
