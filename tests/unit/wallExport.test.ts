// The LV wall export (the command line's `heartmesh myocardium` in the app): when it can be built
// (both LV surfaces run with the settings in the panel; a mesh of other parameters is never used),
// what the buttons say otherwise, the file name and header, the figures line, and the export
// panel's wall group on the fake DOM (building, saving, figures, a failure shown and survived).
import { beforeEach, describe, expect, it, vi } from 'vitest';
import type { WallFormat, WallSummary } from '../../web/src/core-client/protocol';
import { DEFAULT_OPTIONS } from '../../web/src/core-client/protocol';
import { KeptSurfaces, settingsKey } from '../../web/src/app/keptSurfaces';
import {
  WALL_MIN_THICKNESS_MM, wallErrorText, wallFiguresText, wallFiguresTitle, wallFileName, wallFormatTitle, wallHeaderLines, wallReadiness,
} from '../../web/src/io/export/wall';
import type { FakeElement } from './fakeDom';
import { exportSource, useFakeDocument } from './panelHarness';
import { KEY, formatButtons, keptOf, mesh, patient1Info } from './wallFixtures';

const saved: { data: unknown; name: string; type: string }[] = [];
vi.mock('../../web/src/io/download', () => ({
  download: (data: unknown, name: string, type: string) => saved.push({ data, name, type }),
}));
const { ExportPanel } = await import('../../web/src/io/ExportPanel');

const summary: WallSummary = {
  surfaces: { endo: 'LV_ENDO', epi: 'LV_EPI' },
  format: 'obj',
  vertices: 1557,
  triangles: 3110,
  wall_volume_ml: 99.54830215721525,
  myocardial_mass_g: 104.52571726507601,
  density_g_per_ml: 1.05,
  cavity_volume_ml: 135.0049193600555,
  thickness_mm: { mean: 7.111881237391894, median: 6.694139338009947, p95: 11.2, min: 2.806195812860196, max: 15.590515923974527, count: 1557 },
  regions: [
    { id: 1, name: 'epicardium', triangles: 1475 },
    { id: 2, name: 'endocardium', triangles: 1495 },
    { id: 3, name: 'base', triangles: 140 },
  ],
  endo_epi_crossings: 0,
  folded_edges: 0,
  endocardium_moved: { min_thickness_mm: 1, vertices: 0, max_mm: 0 },
  epicardium_moved: { min_thickness_mm: 1, vertices: 0, max_mm: 0 },
  base_plane: { origin: [6.6, -8.6, -8.6], normal: [-0.48, 0.62, 0.62] },
};

const info = patient1Info('RV_ENDO');

describe('settingsKey', () => {
  it('is the same whatever order the parameters and options were set in, and differs with any value', () => {
    const a = settingsKey({ beta: 0.1, iterations: 250 }, 'auto', { soften_conflicts: true, align_slices: false });
    const b = settingsKey({ iterations: 250, beta: 0.1 }, 'auto', { align_slices: false, soften_conflicts: true });
    expect(a).toBe(b);
    expect(settingsKey({ beta: 0.2, iterations: 250 }, 'auto', { soften_conflicts: true, align_slices: false })).not.toBe(a);
    expect(settingsKey({ beta: 0.1, iterations: 250 }, 'none', { soften_conflicts: true, align_slices: false })).not.toBe(a);
    expect(settingsKey({ beta: 0.1, iterations: 250 }, 'auto', { soften_conflicts: true, align_slices: true })).not.toBe(a);
  });
});

describe('KeptSurfaces', () => {
  it('keeps each mesh with its settings and, when given, its full-precision vertices (copies)', () => {
    const kept = new KeptSurfaces();
    kept.bind('a.csv\n');
    const p = new Float32Array([1, 2, 3, 4, 5, 6, 7, 8, 9]);
    const p64 = Float64Array.from([1.000000001, 2, 3, 4, 5, 6, 7, 8, 9]);
    kept.keep('LV_ENDO', p, new Uint32Array([0, 1, 2]), 'k1', p64);
    kept.keep('LV_EPI', p, new Uint32Array([0, 1, 2]), 'k2');
    p64[0] = 0;
    const endo = kept.get('LV_ENDO')!;
    expect(endo.settings).toBe('k1');
    expect(endo.positions64?.[0]).toBe(1.000000001);
    expect(kept.get('LV_EPI')?.positions64).toBeUndefined();
    // A full-precision array of another length (another mesh) is not kept with this one.
    kept.keep('LV_EPI', p, new Uint32Array([0, 1, 2]), 'k3', new Float64Array(6));
    expect(kept.get('LV_EPI')?.positions64).toBeUndefined();
    expect(kept.get('LV_EPI')?.settings).toBe('k3');
    expect(kept.others('LV_ENDO').map((m) => m.surface)).toEqual(['LV_EPI']);
    kept.bind('b.csv\n');
    expect(kept.get('LV_ENDO')).toBeUndefined();
  });
});

describe('wallReadiness', () => {
  const surfaces = ['LV_ENDO', 'LV_EPI', 'RV_ENDO'];

  it('is ready once both LV surfaces were run with the settings in the panel', () => {
    const endo = mesh('LV_ENDO');
    const epi = mesh('LV_EPI');
    const r = wallReadiness(surfaces, keptOf(endo, epi), KEY);
    expect(r.ready).toBe(true);
    if (!r.ready) return;
    expect(r.endo).toBe(endo);
    expect(r.epi).toBe(epi);
    expect(r.title).toMatch(/^The LV wall: the LV_ENDO and LV_EPI meshes cut at the base and joined into one closed solid \(their last runs, with these parameters\)/);
    // Another mesh of a surface is another wall.
    const again = wallReadiness(surfaces, keptOf(endo, mesh('LV_EPI', KEY, 5)), KEY);
    expect(again.ready && again.key !== r.key).toBe(true);
  });

  it('says what is missing: a file, its contours, a run, or a run with these parameters', () => {
    expect(wallReadiness(null, keptOf(), KEY)).toMatchObject({ ready: false, title: expect.stringMatching(/: open a file with LV_ENDO and LV_EPI contours$/) });
    expect(wallReadiness(['LV_ENDO', 'RV_ENDO'], keptOf(mesh('LV_ENDO')), KEY).title).toMatch(/: this file has no LV_EPI contours$/);
    expect(wallReadiness(['RV_ENDO'], keptOf(), KEY).title).toMatch(/: this file has no LV_ENDO and no LV_EPI contours$/);
    expect(wallReadiness(surfaces, keptOf(mesh('RV_ENDO')), KEY).title).toMatch(/: run LV_ENDO and LV_EPI first \(Surface menu, or All\)$/);
    expect(wallReadiness(surfaces, keptOf(mesh('LV_ENDO')), KEY).title).toMatch(/: run LV_EPI too \(Surface menu, or All\)$/);
    const other = settingsKey({ iterations: 250, beta: 0.2 }, 'auto', DEFAULT_OPTIONS);
    const stale = wallReadiness(surfaces, keptOf(mesh('LV_ENDO'), mesh('LV_EPI', other)), KEY);
    expect(stale.ready).toBe(false);
    expect(stale.title).toMatch(/: LV_EPI was last run with other parameters; run it again with these \(Surface menu, or All\)$/);
    // The settings changed after both runs: neither mesh is of them.
    expect(wallReadiness(surfaces, keptOf(mesh('LV_ENDO'), mesh('LV_EPI')), other).title).toMatch(/: LV_ENDO and LV_EPI were last run with other parameters; run them again/);
  });

  it('matches the file\'s names whatever their case', () => {
    const r = wallReadiness(['lv_endo', 'Lv_Epi'], keptOf(mesh('lv_endo'), mesh('Lv_Epi')), KEY);
    expect(r.ready && [r.endo.surface, r.epi.surface]).toEqual(['lv_endo', 'Lv_Epi']);
  });
});

describe('the wall file', () => {
  it('is named after the input like the surface exports, with LV_wall for the surface', () => {
    expect(wallFileName(info, 'obj')).toBe('patient1-ED-LV_wall.obj');
    expect(wallFileName({ ...info, fileName: 'seg.nii.gz', frame: '9' }, 'vtk')).toBe('seg-LV_wall-frame9.vtk');
    expect(wallFileName({ ...info, fileName: 'my heart.csv' }, 'stl')).toBe('my_heart-LV_wall.stl');
  });

  it('carries the app version, the input, the settings and the minimum thickness after the command line\'s comment', () => {
    const lines = wallHeaderLines(info, 'LV_ENDO', 'LV_EPI', WALL_MIN_THICKNESS_MM);
    expect(lines[0]).toBe('heartmesh 0.1.0 (core 0.1.0), units: mm');
    expect(lines[1]).toBe('input: patient1-ED.csv surface: LV_ENDO + LV_EPI');
    expect(lines[2]).toMatch(/^lids: auto iterations=250 beta=0\.1 smoothing_method=laplacian-affine /);
    expect(lines[3]).toBe('min_thickness=1 mm (endocardial vertices closer to the epicardium moved under it)');
    expect(wallHeaderLines(info, 'LV_ENDO', 'LV_EPI', null)[3]).toBe('min_thickness=off');
  });

  it('names what each format carries', () => {
    expect(wallFormatTitle('stl')).toMatch(/STL has no place for the regions/);
    expect(wallFormatTitle('obj')).toMatch(/g epicardium, g endocardium, g base/);
    expect(wallFormatTitle('vtk')).toMatch(/cell data region \(1 epicardium, 2 endocardium, 3 base\), point data thickness \(mm\)/);
  });
});

describe('the figures line', () => {
  it('gives the wall volume, mass, cavity and mean thickness', () => {
    expect(wallFiguresText(summary)).toBe('Wall 99.5 ml · mass 104.5 g · cavity 135.0 ml (both below the base) · thickness 7.1 mm mean');
    const title = wallFiguresTitle(summary);
    expect(title).toContain('LV_ENDO + LV_EPI: 1557 vertices, 3110 triangles, closed');
    expect(title).toContain('regions (triangles): 1 epicardium 1475, 2 endocardium 1495, 3 base 140');
    expect(title).toContain('thickness min 2.8, median 6.7, max 15.6 mm');
    expect(title).toContain('mass = 1.05 g/ml x wall volume');
  });

  it('notes vertices moved to keep the wall thick enough, and warns of crossings', () => {
    const moved = { ...summary, endocardium_moved: { min_thickness_mm: 1, vertices: 12, max_mm: 0.8437 } };
    expect(wallFiguresText(moved)).toBe(
      'Wall 99.5 ml · mass 104.5 g · cavity 135.0 ml (both below the base) · thickness 7.1 mm mean. ' +
        '12 vertices of the endocardium moved up to 0.84 mm under the epicardium, to keep the wall at least 1 mm thick',
    );
    const both = { ...moved, epicardium_moved: { min_thickness_mm: 1, vertices: 1, max_mm: 0.2 } };
    expect(wallFiguresText(both)).toMatch(
      /\. 12 vertices of the endocardium moved up to 0\.84 mm under the epicardium, 1 vertex of the epicardium up to 0\.20 mm out over the endocardium, to keep the wall at least 1 mm thick$/,
    );
    const crossing = { ...summary, endo_epi_crossings: 3, thickness_mm: { ...summary.thickness_mm, count: 0 } };
    expect(wallFiguresText(crossing)).toBe(
      'Wall 99.5 ml · mass 104.5 g · cavity 135.0 ml (both below the base). ⚠ the endocardium passes through the epicardium (3 crossing triangle pairs): volume meshers will refuse it',
    );
  });

  it('says why a wall was not built', () => {
    expect(wallErrorText('the LV wall: degenerate input: the base plane cuts the epicardium in 2 outlines, not one')).toBe(
      '⚠ The LV wall could not be built: degenerate input: the base plane cuts the epicardium in 2 outlines, not one',
    );
    expect(wallErrorText('the worker crashed earlier')).toBe('⚠ The LV wall could not be built: the worker crashed earlier');
  });
});

describe('the export panel\'s LV wall', () => {
  useFakeDocument();
  beforeEach(() => {
    saved.length = 0;
  });

  function panel(wallFile: (f: WallFormat) => Promise<{ summary: WallSummary; bytes: Uint8Array }> | null) {
    const failed: unknown[] = [];
    const asked: WallFormat[] = [];
    const p = new ExportPanel(
      exportSource(info, {
        wallFile: (f) => {
          asked.push(f);
          return wallFile(f);
        },
        failed: (e) => failed.push(e),
      }),
    );
    const root = p.element as unknown as FakeElement;
    return { p, root, buttons: formatButtons(root, 'wall'), failed, asked, figures: root.byTestId('wall-figures')! };
  }
  const ready = () => wallReadiness(['LV_ENDO', 'LV_EPI'], (s) => mesh(s), KEY);
  const settle = () => new Promise((r) => setTimeout(r, 0));

  it('is disabled, saying why, until the wall can be built', () => {
    const { p, buttons, root } = panel(() => null);
    expect(buttons.map((b) => b.disabled)).toEqual([true, true, true, true]);
    expect(buttons[0].title).toMatch(/open a file with LV_ENDO and LV_EPI contours$/);
    p.setWall(wallReadiness(['LV_ENDO', 'LV_EPI'], (s) => (s === 'LV_ENDO' ? mesh(s) : undefined), KEY));
    expect(buttons.map((b) => b.disabled)).toEqual([true, true, true, true]);
    expect(buttons[1].title).toMatch(/run LV_EPI too/);
    expect(root.byTestId('wall-export')!.dataset.ready).toBe('0');
    p.setWall(ready());
    expect(buttons.map((b) => b.disabled)).toEqual([false, false, false, false]);
    expect(buttons[1].title).toBe(wallFormatTitle('obj'));
    expect(root.byTestId('wall-export')!.dataset.ready).toBe('1');
  });

  it('builds, saves <base>-LV_wall.<ext> and shows the figures, which go when the meshes change', async () => {
    const bytes = new TextEncoder().encode('# heartmesh 0.1.0\n');
    let resolve!: (v: { summary: WallSummary; bytes: Uint8Array }) => void;
    const { p, buttons, figures, asked } = panel(() => new Promise((r) => (resolve = r)));
    p.setWall(ready());
    buttons[3].fire('click');
    expect(asked).toEqual(['vtk']);
    expect(buttons.every((b) => b.disabled)).toBe(true);
    expect(figures.hidden).toBe(false);
    expect(figures.dataset.state).toBe('busy');
    expect(figures.textContent).toBe('building the LV wall…');
    resolve({ summary, bytes });
    await settle();
    expect(saved).toHaveLength(1);
    expect(saved[0].name).toBe('patient1-ED-LV_wall.vtk');
    expect(saved[0].data).toEqual(bytes);
    expect(figures.dataset.state).toBe('done');
    expect(figures.textContent).toBe(wallFiguresText(summary));
    expect(Number(figures.dataset.wallMl)).toBe(summary.wall_volume_ml);
    expect(Number(figures.dataset.cavityMl)).toBe(summary.cavity_volume_ml);
    expect(Number(figures.dataset.massG)).toBe(summary.myocardial_mass_g);
    expect(buttons.every((b) => !b.disabled)).toBe(true);
    // The same meshes (a later run of another surface): the figures stay.
    p.setWall(ready());
    expect(figures.hidden).toBe(false);
    // Parameters changed: the meshes are stale, the figures go.
    p.setWall(wallReadiness(['LV_ENDO', 'LV_EPI'], (s) => mesh(s), 'other'));
    expect(figures.hidden).toBe(true);
    expect(figures.dataset.state).toBeUndefined();
  });

  it('shows why a wall could not be built, reports it, and stays usable', async () => {
    let fail = true;
    const { p, buttons, figures, failed } = panel(() =>
      fail
        ? Promise.reject({ code: 'degenerate', message: 'the LV wall: degenerate input: the base plane cuts the epicardium in 2 outlines, not one' })
        : Promise.resolve({ summary, bytes: new Uint8Array(3) }),
    );
    p.setWall(ready());
    buttons[1].fire('click');
    await settle();
    expect(saved).toHaveLength(0);
    expect(figures.dataset.state).toBe('error');
    expect(figures.textContent).toBe('⚠ The LV wall could not be built: degenerate input: the base plane cuts the epicardium in 2 outlines, not one');
    expect(figures.classList.contains('warn')).toBe(true);
    expect(failed).toEqual([{ code: 'degenerate', message: 'the LV wall: degenerate input: the base plane cuts the epicardium in 2 outlines, not one' }]);
    expect(buttons.every((b) => !b.disabled)).toBe(true);
    fail = false;
    buttons[0].fire('click');
    await settle();
    expect(saved.map((s) => s.name)).toEqual(['patient1-ED-LV_wall.stl']);
    expect(figures.dataset.state).toBe('done');
    expect(figures.classList.contains('warn')).toBe(false);
  });
});
