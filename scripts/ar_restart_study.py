#!/usr/bin/env python3
"""PPP-AR from fresh starts: ppp_solve from many start times of the shared real data, with the
wrong fixes (fixed epochs > 10 cm 3D from the reference), the first fix and the time below 10 cm
for good of every run, and their totals and medians.

usage: scripts/ar_restart_study.py BIN_DIR OUT_DIR SET [estimator] [ppp_solve args...]
  BIN_DIR   where ppp_solve is (build_ws/devel/lib/ppp_bayes_tree)
  SET       ccj2a: CCJ2 2021-210 from 00:00 to 00:45 every 5 min, IGS14 satellite antennas and the
                   receiver antenna of igs20_zim2_gps_trim.atx
            ccj2b: the same with the IGS14 satellite antennas alone
            esbc:  ESBC 2020-177, one-hour runs from every hour (GRG integer-recovery clocks);
                   reference = the day's float static position (doc/beidou.md)
  estimator ekf (default), smoother or both
  e.g. scripts/ar_restart_study.py build_ws/devel/lib/ppp_bayes_tree /tmp/rs esbc both --config my.yaml
The shared data is read from ../shared/data (PPP_SHARED_DATA overrides)."""
import csv, os, subprocess, sys, statistics
from concurrent.futures import ThreadPoolExecutor

D = os.environ.get('PPP_SHARED_DATA', os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'shared', 'data'))
C = D + '/ccj2-2021-210'
E = D + '/esbc-2020-177'
binp, out, which = sys.argv[1], sys.argv[2], sys.argv[3]
est = sys.argv[4] if len(sys.argv) > 4 else 'ekf'
extra = sys.argv[5:]
env = dict(os.environ)
if os.path.exists(os.path.join(binp, 'libppp_core.so')):
    env['LD_LIBRARY_PATH'] = binp

def ccj2(atx2):
    base = ['--obs', C + '/ccj22100.21o', '--sp3', C + '/WUM0MGXRAP_20212100000_01D_01M_ORB.SP3.gz',
            '--clk', C + '/WUM0MGXRAP_20212100000_01D_30S_CLK.CLK.gz', '--bia', C + '/WUM0MGXRAP_20212100000_01D_01D_ABS.BIA.gz',
            '--blq', D + '/oceanload/ccj2_fes2004.blq', '--atx', D + '/antex/igs14_2178_satellites.atx']
    if atx2: base += ['--atx', D + '/antex/igs20_zim2_gps_trim.atx']
    base += ['--truth', '-4490605.094,3483895.065,2884928.334']
    return [(f'm{m:02d}', base + ['--start', f'2021/07/29 00:{m:02d}:00']) for m in range(0, 50, 5)]

def esbc():
    base = ['--obs', E + '/ESBC00DNK_R_20201770000_01D_30S_MO.crx.gz', '--sp3', E + '/GRG0MGXFIN_20201770000_01D_15M_ORB.SP3.gz',
            '--clk', E + '/GRG0MGXFIN_20201770000_01D_30S_CLK.CLK.gz', '--blq', D + '/oceanload/esbc_fes2014b.blq',
            '--atx', D + '/antex/igs14_2178_satellites.atx', '--atx', D + '/antex/igs05_esbc_receiver_trim.atx',
            '--truth', '3582104.7570,532590.1752,5232755.1289']
    jobs = []
    for h in range(24):
        end = f'2020/06/25 {h+1:02d}:00:00' if h < 23 else '2020/06/25 23:59:30'
        jobs.append((f'h{h:02d}', base + ['--start', f'2020/06/25 {h:02d}:00:00', '--end', end]))
    return jobs

jobs = {'ccj2a': lambda: ccj2(True), 'ccj2b': lambda: ccj2(False), 'esbc': esbc}[which]()

def run(job):
    name, args = job
    o = os.path.join(out, which, name)
    os.makedirs(o, exist_ok=True)
    r = subprocess.run([binp + '/ppp_solve'] + args + ['--estimator', est, '--out', o] + extra,
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, env=env)
    open(o + '.log', 'wb').write(r.stdout)
    return name, o, r.returncode

def stats(path):
    rows = [r for r in csv.DictReader(open(path)) if r['err3d_m']]
    if not rows: return None
    t0 = float(rows[0]['tow_s'])
    fx = [r for r in rows if r['status'] == 'ppp-fixed']
    wrong = [r for r in fx if float(r['err3d_m']) > 0.10]
    first = (float(fx[0]['tow_s']) - t0) / 60 if fx else None
    conv = None
    for i in range(len(rows)):
        if all(float(r['err3d_m']) < 0.10 for r in rows[i:]):
            conv = (float(rows[i]['tow_s']) - t0) / 60; break
    mean = statistics.mean(float(r['err3d_m']) for r in rows)
    return dict(n=len(rows), fixed=len(fx), wrong=len(wrong), first=first, conv=conv, mean=mean,
                maxwrong=max((float(r['err3d_m']) for r in wrong), default=0.0))

with ThreadPoolExecutor(2) as ex:
    results = list(ex.map(run, jobs))
tot = {}
for name, o, rc in results:
    files = [f for f in sorted(os.listdir(o)) if f.endswith('.csv') and ('ekf.csv' in f or 'smoother_filtered.csv' in f or 'smoother_smoothed.csv' in f)]
    for f in files:
        s = stats(os.path.join(o, f))
        if not s: continue
        kind = f.split('_', 1)[1][:-4]
        print(f"{which} {name} {kind:18s} rc={rc} n={s['n']} fixed={s['fixed']} wrong={s['wrong']} "
              f"first={s['first']} conv={s['conv']} mean={s['mean']*100:.2f}cm maxwrong={s['maxwrong']*100:.1f}cm")
        t = tot.setdefault(kind, dict(fixed=0, wrong=0, first=[], conv=[], mean=[], nofix=0))
        t['fixed'] += s['fixed']; t['wrong'] += s['wrong']; t['mean'].append(s['mean'])
        if s['first'] is not None: t['first'].append(s['first'])
        else: t['nofix'] += 1
        if s['conv'] is not None: t['conv'].append(s['conv'])
for k, t in tot.items():
    med = lambda v: statistics.median(v) if v else None
    print(f"TOTAL {which} {k}: fixed {t['fixed']} wrong {t['wrong']} first fix median {med(t['first'])} max "
          f"{max(t['first'], default=None)} (no fix {t['nofix']}) conv median {med(t['conv'])} max {max(t['conv'], default=None)} "
          f"mean3d median {med(t['mean'])*100:.2f}cm")
