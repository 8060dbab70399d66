#!/usr/bin/python3
"""Compaction profile through the height of a DEM compaction test (anticrack `Loading/Test = compaction`).

Reads RUN/snapshots/snapshot_*.h5 (particles/position, blocked, clump_id), RUN/history.h5 and
RUN/summary.json (layer thickness h, compaction-curve reading). Optionally EARLY, a run of the same
scene and seed with denser snapshots over the first steps (the engine is bit-reproducible), for the
pre-peak and peak stages.

Strain measure: the deformable layer = the spheres that are neither fixed (base) nor in the clump
(platen); h = highest base centre .. lowest clump centre at step 0 (= summary specimen.layer_thickness_m).
The layer is cut into N slices of equal initial thickness by the spheres' INITIAL height z0
(Lagrangian slices). The vertical displacement u_z(z0) of every layer sphere is fitted by least
squares with a continuous piecewise-linear field whose nodes are the slice bounds, with u = 0 at
the base (fixed) and u = u_clump at the platen (rigid): slice strain = -(U_top - U_bottom) / dz
(compression positive). Check: an independent straight-line fit u_z vs z0 per slice ("slope").
Global strain eps = -u_clump / h (the calibration's layer strain, dem/lab/compaction_curve.h).

usage: profile.py RUN [--early EARLY] [--slices N] [--png OUT.png] [--label r0] [--json OUT.json]
       profile.py --combined OUT.png RUN:EARLY RUN:EARLY ...   (one row per realization)
"""
import argparse
import glob
import json
import os
import re

import h5py
import numpy as np


def snapshot_files(run):
    files = glob.glob(os.path.join(run, 'snapshots', 'snapshot_*.h5'))
    return sorted(files, key=lambda f: int(re.findall(r'(\d+)\.h5$', f)[0]))


def read_snapshot(f):
    with h5py.File(f, 'r') as h:
        return (int(h.attrs['step']), float(h.attrs['time']), h['particles/position'][:, 2].copy(),
                h['particles/blocked'][:].astype(bool), h['particles/clump_id'][:].copy())


def read_bonds(f):
    with h5py.File(f, 'r') as h:
        return h['bonds/i'][:], h['bonds/j'][:], h['bonds/state'][:]


class Layer:
    def __init__(self, snap0, nslices):
        step, _, z0, blocked, clump = read_snapshot(snap0)
        assert step == 0
        self.z0 = z0
        self.base = blocked
        self.clump = clump >= 0
        self.layer = ~self.base & ~self.clump
        self.zb = z0[self.base].max()
        self.zc = z0[self.clump].min()
        self.h = self.zc - self.zb
        self.n = nslices
        self.bounds = np.linspace(self.zb, self.zc, nslices + 1)
        self.dz = self.h / nslices
        zl = z0[self.layer]
        # hat functions of the interior nodes 1..n-1 at every layer sphere; nodes 0 and n are known
        s = np.clip((zl - self.zb) / self.dz, 0, nslices - 1e-12)
        k = np.floor(s).astype(int)
        t = s - k
        self.k, self.t = k, t
        A = np.zeros((zl.size, nslices + 1))
        A[np.arange(zl.size), k] = 1 - t
        A[np.arange(zl.size), k + 1] += t
        self.A = A
        self.slice_of = k
        self.counts = np.bincount(k, minlength=nslices)
        # bonds: slice of the initial midpoint height (bonds touching the base or the platen included
        # in the end slices)
        bi, bj, _ = read_bonds(snap0)
        zm = 0.5 * (z0[bi] + z0[bj])
        self.bond_slice = np.clip(np.floor((zm - self.zb) / self.dz).astype(int), 0, nslices - 1)
        self.bond_inner = ~((self.base[bi] & self.base[bj]) | (self.clump[bi] & self.clump[bj]))
        self.bonds_per_slice = np.bincount(self.bond_slice[self.bond_inner], minlength=nslices)

    def broken(self, f):
        _, _, st = read_bonds(f)
        b = (st > 0) & self.bond_inner
        return np.bincount(self.bond_slice[b], minlength=self.n) / self.bonds_per_slice

    def profile(self, z):
        u = z - self.z0
        uc = u[self.clump].mean()          # rigid platen: all members move alike
        ul = u[self.layer]
        # known nodes: U0 = 0 (base), Un = uc (platen)
        rhs = ul - self.A[:, -1] * uc
        Ai = self.A[:, 1:-1]
        Ui, *_ = np.linalg.lstsq(Ai, rhs, rcond=None)
        U = np.concatenate([[0.0], Ui, [uc]])
        strain = -(np.diff(U)) / self.dz
        # check: independent straight-line fit per slice
        slope = np.empty(self.n)
        zl = self.z0[self.layer]
        for j in range(self.n):
            m = self.slice_of == j
            slope[j] = -np.polyfit(zl[m], ul[m], 1)[0]
        return -uc / self.h, strain, slope, U


def cov(x):
    return float(np.std(x) / np.mean(x)) if np.mean(x) != 0 else np.nan


def analyse(run, early, nslices):
    files = snapshot_files(run)
    L = Layer(files[0], nslices)
    summ = json.load(open(os.path.join(run, 'summary.json')))['dem']
    cc = summ['failure_analysis']['compaction_curve']
    h_summary = summ['specimen']['layer_thickness_m']
    H0 = summ['specimen']['height_m']
    recs = []
    for f in files:
        step, time, z, *_ = read_snapshot(f)
        eps, strain, slope, U = L.profile(z)
        recs.append(dict(step=step, time=time, eps=eps, strain=strain, slope=slope, U=U, src='main', f=f))
    if early:
        ef = snapshot_files(early)
        Le = Layer(ef[0], nslices)
        assert np.array_equal(Le.z0, L.z0), 'early run is not the same sample'
        for f in ef:
            step, time, z, *_ = read_snapshot(f)
            eps, strain, slope, U = L.profile(z)
            recs.append(dict(step=step, time=time, eps=eps, strain=strain, slope=slope, U=U, src='early', f=f))
        # consistency: a step in both runs must agree (bit-reproducible engine)
        both = {r['step'] for r in recs if r['src'] == 'early'} & {r['step'] for r in recs if r['src'] == 'main'}
        for s in sorted(both)[:3]:
            a = [r for r in recs if r['step'] == s]
            assert np.allclose(a[0]['U'], a[1]['U'], rtol=0, atol=1e-15), f'runs differ at step {s}'
        d = {}
        for r in recs:
            d.setdefault(r['step'], r)
        recs = [d[s] for s in sorted(d)]
    with h5py.File(os.path.join(run, 'history.h5'), 'r') as hf:
        hist = dict(step=hf['step'][:], eps=hf['normal_strain'][:] * H0 / L.h,
                    sigma=hf['base_normal_stress'][:], broken=hf['broken_bond_fraction'][:])
    return L, recs, cc, hist, h_summary


def nearest(recs, eps=None, step=None):
    if step is not None:
        return min(recs, key=lambda r: abs(r['step'] - step))
    return min(recs, key=lambda r: abs(r['eps'] - eps))


def stage_list(recs, hist, cc):
    ep, es, ed, ex = cc['peak_strain'], cc['softening_end_strain'], cc['lock_up_strain'], cc['regain_strain']
    peak_step = int(hist['step'][np.argmax(np.where(hist['eps'] < 0.01, hist['sigma'], -1))])
    return [('pre-peak (~eps_p/2)', nearest(recs, eps=ep / 2)),
            ('peak', nearest(recs, step=peak_step)),
            ('end of drop (eps_s)', nearest(recs, eps=es)),
            ('early plateau', nearest(recs, eps=0.03)),
            ('mid plateau', nearest(recs, eps=(es + ed) / 2)),
            ('late plateau', nearest(recs, eps=0.17)),
            ('lock-up (eps_d)', nearest(recs, eps=ed)),
            ('regain sigma_p (eps_x)', nearest(recs, eps=ex)),
            ('after lock-up (end)', recs[-1])]


def combined(png, pairs, nslices):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(len(pairs), 3, figsize=(17, 4.6 * len(pairs)), squeeze=False)
    for row, pair in enumerate(pairs):
        run, early = (pair.split(':') + [None])[:2]
        L, recs, cc, hist, _ = analyse(run, early, nslices)
        st = stage_list(recs, hist, cc)
        x = ax[row, 0]
        x.plot(hist['eps'], hist['sigma'] / 1e3, 'k-', lw=0.8)
        for name, r in st:
            x.plot(r['eps'], np.interp(r['eps'], hist['eps'], hist['sigma']) / 1e3, 'o', ms=5, label=name)
        x.axvline(cc['lock_up_strain'], color='gray', ls=':')
        x.set_xlabel('layer strain u/h'); x.set_ylabel('base normal stress [kPa]')
        x.set_title(f'{os.path.basename(run)}: stress-strain (history.h5); dotted = lock-up eps_d')
        x.legend(fontsize=6, loc='upper left')
        xin = x.inset_axes([0.42, 0.55, 0.3, 0.3]); m = hist['eps'] < 0.02
        xin.plot(hist['eps'][m], hist['sigma'][m] / 1e3, 'k-', lw=0.8); xin.tick_params(labelsize=6)
        x = ax[row, 1]
        zb = (L.bounds - L.zb) / L.h
        for name, r in st:
            v = r['strain'] / r['eps']
            x.step(np.concatenate([v, [v[-1]]]), zb, where='post',
                   label=f'{name}: eps={r["eps"]:.3f} CoV={cov(r["strain"]):.2f}')
        x.axvline(1, color='k', ls='--', lw=0.8)
        x.set_xlabel('slice strain / global strain (1 = homogeneous)'); x.set_ylabel('z0/h (0 base, 1 platen)')
        x.set_title(f'{nslices} Lagrangian slices: cumulative strain profiles'); x.legend(fontsize=6)
        x.set_xlim(0, 3.5)
        x = ax[row, 2]
        eps = np.array([r['eps'] for r in recs]); S = np.array([r['strain'] for r in recs])
        o = np.argsort(eps); e, Ss = eps[o], S[o]
        grid = np.linspace(0, e.max(), 100)
        Sg = np.array([np.interp(grid, e, Ss[:, j]) for j in range(L.n)])
        rate = np.diff(Sg, axis=1) / np.diff(grid)
        im = x.pcolormesh(grid, zb, rate, cmap='magma', vmin=0, vmax=2.5)
        fig.colorbar(im, ax=x, label='d(slice strain)/d(global strain)')
        x.axvline(cc['lock_up_strain'], color='c', ls=':')
        x.set_xlabel('global layer strain u/h'); x.set_ylabel('z0/h')
        x.set_title('where the layer compacts (1 = homogeneous)')
    fig.tight_layout(); fig.savefig(png, dpi=100)
    print('# wrote', png)


def main():
    import sys
    if len(sys.argv) > 1 and sys.argv[1] == '--combined':
        return combined(sys.argv[2], sys.argv[3:], 8)
    ap = argparse.ArgumentParser()
    ap.add_argument('run')
    ap.add_argument('--early')
    ap.add_argument('--slices', type=int, default=8)
    ap.add_argument('--png')
    ap.add_argument('--label', default='')
    ap.add_argument('--json')
    a = ap.parse_args()
    L, recs, cc, hist, h_summary = analyse(a.run, a.early, a.slices)
    eps_all = np.array([r['eps'] for r in recs])
    S = np.array([r['strain'] for r in recs])
    sig_at = lambda e: float(np.interp(e, hist['eps'], hist['sigma']))
    print(f'# {a.run}: layer h = {L.h*1e3:.4f} mm (summary {h_summary*1e3:.4f}), {L.layer.sum()} layer spheres, '
          f'{a.slices} slices of {L.dz*1e3:.3f} mm, spheres per slice {L.counts.tolist()}')
    ep, es, ed, ex = cc['peak_strain'], cc['softening_end_strain'], cc['lock_up_strain'], cc['regain_strain']
    print(f'# curve: peak {cc["peak_stress_Pa"]/1e3:.2f} kPa at eps_p {ep:.5f}; residual {cc["residual_stress_Pa"]/1e3:.2f} kPa '
          f'from eps_s {es:.5f}; lock-up eps_d {ed:.4f}, regains sigma_p at eps_x {ex:.4f}; end eps {eps_all.max():.4f}')
    stages = stage_list(recs, hist, cc)
    hdr = 'stage                    step   eps     sigma[kPa] | ' + ' '.join(f's{j+1:<6d}' for j in range(a.slices)) + \
          '| min/mean  CoV   CoV(slope)'
    print('# slice strains, cumulative from step 0 (s1 = bottom, at the base; s%d = top, under the platen)' % a.slices)
    print(hdr)
    out = []
    for name, r in stages:
        s = r['strain']
        print(f'{name:24s} {r["step"]:6d} {r["eps"]:.4f}  {sig_at(r["eps"])/1e3:8.2f}  | ' +
              ' '.join(f'{v:7.4f}' for v in s) + f'| {s.min()/s.mean():6.2f} {cov(s):6.3f} {cov(r["slope"]):6.3f}')
        out.append(dict(stage=name, step=r['step'], eps=r['eps'], sigma=sig_at(r['eps']), strain=s.tolist(),
                        slope=r['slope'].tolist(), cov=cov(s), cov_slope=cov(r['slope'])))
    print('# increments between stages (where the layer deforms at that moment)')
    prev = None
    for name, r in stages:
        if prev is not None and r['eps'] > prev['eps']:
            d = r['strain'] - prev['strain']
            de = r['eps'] - prev['eps']
            print(f'{"-> " + name:24s} deps {de:.4f}          | ' + ' '.join(f'{v/de:7.2f}' for v in d) +
                  f'| (slice increment / global increment)  CoV {cov(d):6.3f}')
        prev = r
    print('# broken-bond fraction per slice (bonds by initial midpoint height; bonds inside the base/platen excluded)')
    print('#   bonds per slice', L.bonds_per_slice.tolist())
    for name, r in stages:
        b = L.broken(r['f'])
        print(f'{name:24s} {r["step"]:6d} {r["eps"]:.4f}              | ' + ' '.join(f'{v:7.3f}' for v in b) +
              f'| all {np.sum(b*L.bonds_per_slice)/L.bonds_per_slice.sum():.3f}')
        out[[o['stage'] for o in out].index(name)]['broken'] = b.tolist()
    # initial density per slice vs final strain
    last = stages[-3][1]['strain']
    print(f'# correlation of sphere count per slice (initial density) with the slice strain at lock-up: '
          f'{np.corrcoef(L.counts, stages[-3][1]["strain"])[0, 1]:.2f}')
    if a.json:
        json.dump(dict(run=a.run, slices=a.slices, h=L.h, stages=out, curve=cc), open(a.json, 'w'), indent=1)
    if a.png:
        plot(a, L, recs, stages, hist, cc)


def plot(a, L, recs, stages, hist, cc):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    eps = np.array([r['eps'] for r in recs])
    S = np.array([r['strain'] for r in recs])
    zc = 0.5 * (L.bounds[:-1] + L.bounds[1:])
    zrel = (zc - L.zb) / L.h
    fig, ax = plt.subplots(2, 2, figsize=(13, 10))
    # (a) stress-strain with the stages
    x = ax[0, 0]
    x.plot(hist['eps'], hist['sigma'] / 1e3, 'k-', lw=1)
    for name, r in stages:
        x.plot(r['eps'], np.interp(r['eps'], hist['eps'], hist['sigma']) / 1e3, 'o', label=f'{name} ({r["eps"]:.3f})')
    x.axvline(cc['lock_up_strain'], color='gray', ls=':')
    x.set_xlabel('layer strain u/h'); x.set_ylabel('base normal stress [kPa]')
    x.set_title(f'{a.label} stress-strain (history.h5)'); x.legend(fontsize=7)
    xin = x.inset_axes([0.12, 0.55, 0.3, 0.3])
    m = hist['eps'] < 0.02
    xin.plot(hist['eps'][m], hist['sigma'][m] / 1e3, 'k-', lw=1)
    xin.tick_params(labelsize=6)
    # (b) cumulative profiles at the stages
    x = ax[0, 1]
    for name, r in stages:
        x.step(np.concatenate([r['strain'], [r['strain'][-1]]]), (L.bounds - L.zb) / L.h, where='post',
               label=f'{name}: eps={r["eps"]:.3f}, CoV={cov(r["strain"]):.2f}')
    x.set_xlabel('slice strain (cumulative)'); x.set_ylabel('initial height in layer z0/h (0 = base, 1 = platen)')
    x.set_xscale('symlog', linthresh=1e-3); x.legend(fontsize=7); x.set_title('slice strain profiles')
    # (c) slice strain vs global strain
    x = ax[1, 0]
    for j in range(L.n):
        x.plot(eps, S[:, j], label=f's{j+1} (z0/h {zrel[j]:.2f})')
    x.plot(eps, eps, 'k--', lw=1, label='homogeneous')
    x.axvline(cc['lock_up_strain'], color='gray', ls=':')
    x.set_xlabel('global layer strain u/h'); x.set_ylabel('slice strain'); x.legend(fontsize=7)
    x.set_title('each slice against the global strain')
    # (d) space-time map of the slice strain rate d(slice strain)/d(global strain)
    x = ax[1, 1]
    order = np.argsort(eps)
    e, Ss = eps[order], S[order]
    grid = np.linspace(0, e.max(), 120)
    Sg = np.array([np.interp(grid, e, Ss[:, j]) for j in range(L.n)])
    rate = np.diff(Sg, axis=1) / np.diff(grid)
    im = x.pcolormesh(grid, (L.bounds - L.zb) / L.h, rate, cmap='magma', vmin=0, vmax=np.percentile(rate, 99))
    fig.colorbar(im, ax=x, label='d(slice strain)/d(global strain)  (1 = homogeneous)')
    x.axvline(cc['lock_up_strain'], color='c', ls=':')
    x.set_xlabel('global layer strain u/h'); x.set_ylabel('z0/h')
    x.set_title('where the layer compacts (local strain rate / global)')
    fig.tight_layout()
    fig.savefig(a.png, dpi=110)
    print('# wrote', a.png)


if __name__ == '__main__':
    main()
