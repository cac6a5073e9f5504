#!/usr/bin/env python3
"""Float PPP from fresh starts beside RTKLIB: ppp_solve and Debian's RTKLIB rnx2rtkp (2.4.3,
config/rtklib_ppp_kinematic.conf) from many start times of the same shared real data, each run
scored by the same code (ppp_pos_stats): the time below 10 cm (3D) for good, the mean 3D error
and the median of the first 15 minutes, per run, with their medians and counts.

usage: scripts/rtklib_restart_study.py BIN_DIR OUT_DIR [--starts 0,5,...] [--config FILE] [SET ...]
  BIN_DIR  where ppp_solve, ppp_pos_stats and ppp_rtklib_inputs are (build_ws/devel/lib/ppp_bayes_tree)
  SET      zim2: ZIM2 2026-133, IGS final orbits and clocks (GPS; no phase information: float),
                 starts every 5 min from 00:00 to 00:30 (runs of 30-60 min)
           ccj2: CCJ2 2021-210, WUM orbits and clocks, GPS alone and ambiguity resolution off in
                 both programs (RTKLIB 2.4.3 reads GPS-only orbits here), the same starts
           (default: both)
  --starts  start minutes after 00:00 (default 0,5,...,30)
  --config  a ppp_solve configuration file read after the set's own (a variant to compare)
Both programs get the same observations, orbits, clocks and antenna files; RTKLIB's navigation
file carries the precise clocks (it needs a broadcast record per satellite) and its orbits are a
GPS-only SP3-c copy (ppp_rtklib_inputs), as in scripts/compare_rtklib.sh. ppp_solve runs with its
defaults (ccj2: signals.systems [GPS], ambiguity_resolution.enabled false).
The shared data is read from ../shared/data (PPP_SHARED_DATA overrides). Needs rnx2rtkp (apt
install rtklib)."""
import gzip, json, os, shutil, statistics, subprocess, sys
from concurrent.futures import ThreadPoolExecutor

REPO = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..')
D = os.environ.get('PPP_SHARED_DATA', os.path.join(REPO, '..', 'shared', 'data'))
STARTS_MIN = list(range(0, 35, 5))

SETS = {
    'zim2': dict(
        dir='zim2-2026-133', day='2026/05/13', obs='ZIM200CHE_R_20261330000_01H_30S_MO.rnx',
        sp3='IGS0OPSFIN_20261330000_03H_15M_ORB.SP3', clk='IGS0OPSFIN_20261330000_90M_30S_CLK.CLK',
        bia='COD0OPSFIN_20261330000_01D_01D_OSB.BIA.gz', sat_atx='igs20_zim2_gps_trim.atx',
        rcv_atx='igs20_zim2_gps_trim.atx', our_atx=['igs20_zim2_gps_trim.atx'],
        truth='4331299.5841,567537.7070,4633133.9645', config=None),
    'ccj2': dict(
        dir='ccj2-2021-210', day='2021/07/29', obs='ccj22100.21o',
        sp3='WUM0MGXRAP_20212100000_01D_01M_ORB.SP3.gz', clk='WUM0MGXRAP_20212100000_01D_30S_CLK.CLK.gz',
        bia='WUM0MGXRAP_20212100000_01D_01D_ABS.BIA.gz', sat_atx='igs20_gps_satellites_trim.atx',
        rcv_atx='igs20_zim2_gps_trim.atx', our_atx=['igs20_gps_satellites_trim.atx', 'igs20_zim2_gps_trim.atx'],
        truth='-4490605.094,3483895.065,2884928.334',
        config='measurement_model:\n  signals:\n    systems: [GPS]\nambiguity_resolution:\n  enabled: false\n'),
}


def run(cmd, log):
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    open(log, 'wb').write(r.stdout)
    if r.returncode != 0:
        sys.exit(f'{cmd[0]} failed (exit {r.returncode}), see {log}')


def prepare(binp, out, s):
    """RTKLIB's inputs (navigation file with the precise clocks, GPS-only SP3, plain clocks) and
    its configuration with the set's antenna files; ppp_solve's configuration."""
    ds, ax = os.path.join(D, s['dir']), os.path.join(D, 'antex')
    os.makedirs(out, exist_ok=True)
    nav, sp3, clk = (os.path.join(out, n) for n in ('rtklib.nav', 'rtklib.sp3', 'rtklib.clk'))
    run([binp + '/ppp_rtklib_inputs', 'nav', nav, os.path.join(ds, s['clk'])], os.path.join(out, 'inputs_nav.log'))
    run([binp + '/ppp_rtklib_inputs', 'sp3', sp3, os.path.join(ds, s['sp3'])], os.path.join(out, 'inputs_sp3.log'))
    opener = gzip.open if s['clk'].endswith('.gz') else open
    with opener(os.path.join(ds, s['clk']), 'rb') as src, open(clk, 'wb') as dst:
        shutil.copyfileobj(src, dst)
    conf = []
    for line in open(os.path.join(REPO, 'config', 'rtklib_ppp_kinematic.conf')):
        if line.startswith('file-satantfile'): line = f'file-satantfile    ={os.path.join(ax, s["sat_atx"])}\n'
        if line.startswith('file-rcvantfile'): line = f'file-rcvantfile    ={os.path.join(ax, s["rcv_atx"])}\n'
        conf.append(line)
    open(os.path.join(out, 'rtklib.conf'), 'w').writelines(conf)
    if s['config']:
        open(os.path.join(out, 'ppp.yaml'), 'w').write(s['config'])
    return nav, sp3, clk


def one_start(binp, out, s, inputs, minute, extra_config):
    """Both programs from one start; their ppp_pos_stats summaries."""
    ds, ax = os.path.join(D, s['dir']), os.path.join(D, 'antex')
    nav, sp3, clk = inputs
    tag = f'm{minute:02d}'
    rtk_pos = os.path.join(out, tag + '_rtklib.pos')
    run(['rnx2rtkp', '-k', os.path.join(out, 'rtklib.conf'), '-ts', s['day'], f'00:{minute:02d}:00', '-o', rtk_pos,
         os.path.join(ds, s['obs']), nav, sp3, clk], os.path.join(out, tag + '_rtklib.log'))
    cmd = [binp + '/ppp_solve', '--obs', os.path.join(ds, s['obs']), '--sp3', os.path.join(ds, s['sp3']),
           '--clk', os.path.join(ds, s['clk']), '--bia', os.path.join(ds, s['bia']),
           '--atx'] + [os.path.join(ax, a) for a in s['our_atx']] + [
           '--truth', s['truth'], '--start', f'{s["day"]} 00:{minute:02d}:00', '--estimator', 'ekf',
           '--name', tag, '--out', os.path.join(out, tag)]
    configs = ([os.path.join(out, 'ppp.yaml')] if s['config'] else []) + ([extra_config] if extra_config else [])
    if configs: cmd += ['--config'] + configs
    run(cmd, os.path.join(out, tag + '_ppp_solve.log'))
    ours_pos = os.path.join(out, tag, tag + '_ekf.pos')
    return minute, [stats(binp, p, s['truth'], os.path.join(out, f'{tag}_{w}.json'))
                    for p, w in ((rtk_pos, 'rtklib'), (ours_pos, 'ours'))]


def stats(binp, pos, truth, json_path):
    run([binp + '/ppp_pos_stats', pos, '--truth', truth, '--json', json_path], json_path + '.log')
    j = json.load(open(json_path))
    below = next((c['time_s'] for c in j['convergence'] if abs(c['threshold_m'] - 0.1) < 1e-9), None)
    return dict(below_10cm_min=None if below is None else below / 60.0, mean_cm=100.0 * j['all_epochs']['mean_m'],
                first15_median_cm=100.0 * j['first_window']['median_m'], span_min=j['span_s'] / 60.0)


def fmt_min(v):
    return 'never' if v is None else f'{v:.1f}'


def median_min(values):
    """Median with 'never' above every time."""
    big = 1e9
    m = statistics.median([big if v is None else v for v in values])
    return 'never' if m >= big else f'{m:.1f}'


def report(name, rows):
    print(f'\n## {name}: starts every 5 min (EKF / RTKLIB forward)')
    print('| start | span [min] | below 10 cm for good [min] ours / RTKLIB | mean 3D [cm] ours / RTKLIB '
          '| first 15 min median [cm] ours / RTKLIB |')
    print('|---|---:|---|---|---|')
    for minute, (rtk, ours) in rows:
        print(f'| 00:{minute:02d} | {ours["span_min"]:.1f} | {fmt_min(ours["below_10cm_min"])} / '
              f'{fmt_min(rtk["below_10cm_min"])} | {ours["mean_cm"]:.1f} / {rtk["mean_cm"]:.1f} | '
              f'{ours["first15_median_cm"]:.1f} / {rtk["first15_median_cm"]:.1f} |')
    ours = [o for _, (_, o) in rows]
    rtk = [r for _, (r, _) in rows]
    never_o = sum(o['below_10cm_min'] is None for o in ours)
    never_r = sum(r['below_10cm_min'] is None for r in rtk)
    later = [m for (m, _), o, r in zip(rows, ours, rtk) if r['below_10cm_min'] is not None and
             (o['below_10cm_min'] is None or o['below_10cm_min'] > r['below_10cm_min'])]
    print(f'| median | | {median_min([o["below_10cm_min"] for o in ours])} / '
          f'{median_min([r["below_10cm_min"] for r in rtk])} | '
          f'{statistics.median([o["mean_cm"] for o in ours]):.1f} / {statistics.median([r["mean_cm"] for r in rtk]):.1f} | '
          f'{statistics.median([o["first15_median_cm"] for o in ours]):.1f} / '
          f'{statistics.median([r["first15_median_cm"] for r in rtk]):.1f} |')
    print(f'never below 10 cm: ours {never_o} of {len(rows)}, RTKLIB {never_r} of {len(rows)}; '
          f'ours below 10 cm later than RTKLIB: {len(later)} of {len(rows)} starts'
          + (' (' + ', '.join(f'00:{m:02d}' for m in later) + ')' if later else ''))
    return dict(set=name, runs=[dict(start_min=m, ours=o, rtklib=r) for m, (r, o) in rows])


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    binp, out = sys.argv[1], sys.argv[2]
    args, starts = sys.argv[3:], STARTS_MIN
    if '--starts' in args:
        i = args.index('--starts')
        try:
            starts = [int(v) for v in args[i + 1].split(',')]
        except (IndexError, ValueError):
            sys.exit('--starts needs minutes after 00:00, e.g. 0,5,10')
        if any(not 0 <= m <= 45 for m in starts):
            sys.exit('--starts: each start in 0..45 min (the files hold one hour)')
        del args[i:i + 2]
    extra_config = None
    if '--config' in args:
        i = args.index('--config')
        if i + 1 >= len(args) or not os.path.isfile(args[i + 1]):
            sys.exit('--config needs an existing ppp_solve configuration file')
        extra_config = os.path.abspath(args[i + 1])
        del args[i:i + 2]
    names = args or list(SETS)
    for n in names:
        if n not in SETS: sys.exit(f'unknown set {n} (zim2, ccj2)')
    if shutil.which('rnx2rtkp') is None:
        sys.exit('rnx2rtkp not found (apt install rtklib)')
    results = []
    for n in names:
        o = os.path.join(out, n)
        inputs = prepare(binp, o, SETS[n])
        with ThreadPoolExecutor(max_workers=2) as ex:
            rows = sorted(ex.map(lambda m: one_start(binp, o, SETS[n], inputs, m, extra_config), starts))
        results.append(report(n, rows))
    json.dump(results, open(os.path.join(out, 'rtklib_restarts.json'), 'w'), indent=1)


if __name__ == '__main__':
    main()
