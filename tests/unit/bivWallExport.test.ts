// The biventricular wall export (the command line's `heartmesh myocardium --biventricular` in the
// app): when it can be built (LV_ENDO, RV_ENDO and BIV_EPI run with the settings in the panel; a
// mesh of other parameters is never used), what the buttons say otherwise (a file without RV_EPI
// cannot give BIV_EPI; All leaves BIV_EPI out unless it is the current surface), the file name and
// header, the figures line (patient 1 ED's figures from the CLI's report), and the export panel's
// second wall row on the fake DOM (building, saving, figures, a failure shown and survived, the LV
// row left alone).
import { beforeEach, describe, expect, it, vi } from 'vitest';
import type { WallFormat, WallSummary } from '../../web/src/core-client/protocol';
import { DEFAULT_OPTIONS } from '../../web/src/core-client/protocol';
import { settingsKey } from '../../web/src/app/keptSurfaces';
import {
  bivWallErrorText, bivWallFiguresText, bivWallFiguresTitle, bivWallFileName, bivWallFormatTitle, bivWallHeaderLines, bivWallReadiness,
} from '../../web/src/io/export/bivWall';
import { WALL_MIN_THICKNESS_MM, wallReadiness } from '../../web/src/io/export/wall';
import type { FakeElement } from './fakeDom';
import { exportSource, useFakeDocument } from './panelHarness';
import { KEY, formatButtons, keptOf, mesh, patient1Info } from './wallFixtures';

const saved: { data: unknown; name: string; type: string }[] = [];
vi.mock('../../web/src/io/download', () => ({
  download: (data: unknown, name: string, type: string) => saved.push({ data, name, type }),
}));
const { ExportPanel } = await import('../../web/src/io/ExportPanel');

/** `heartmesh myocardium patient1-ED.csv --biventricular --report` (the summary the binding gives). */
const summary: WallSummary = {
  surfaces: { endo: 'LV_ENDO', epi: 'BIV_EPI', rv_endo: 'RV_ENDO' },
  format: 'obj',
  vertices: 2140,
  triangles: 4276,
  wall_volume_ml: 132.47267309576594,
  myocardial_mass_g: 139.09630675055425,
  density_g_per_ml: 1.05,
  cavity_volume_ml: 135.0049193600555,
  cavities: [
    { region: 'lv_endocardium', volume_ml: 135.0049193600555 },
    { region: 'rv_endocardium', volume_ml: 127.01773160942558 },
  ],
  thickness_mm: { mean: 5.302729512836673, median: 5.523931953645665, p95: 9.818518541597077, min: 0.9999999999999954, max: 12.40445778152254, count: 2140 },
  regions: [
    { id: 1, name: 'epicardium', triangles: 1253 },
    { id: 2, name: 'lv_endocardium', triangles: 1495 },
    { id: 3, name: 'rv_endocardium', triangles: 1302 },
    { id: 4, name: 'base', triangles: 226 },
  ],
  endo_epi_crossings: 0,
  crossings: [],
  folded_edges: 0,
  endocardium_moved: { min_thickness_mm: 1, vertices: 18, max_mm: 1.4503354506794803 },
  epicardium_moved: { min_thickness_mm: 1, vertices: 1, max_mm: 0.2528619253881515 },
  base_plane: { origin: [6.64, -8.57, -8.62], normal: [-0.48, 0.62, 0.62] },
};

const info = patient1Info('BIV_EPI');

/** Patient 1's surfaces as the core lists them: BIV_EPI joined from LV_EPI and RV_EPI. */
const SURFACES = ['LV_ENDO', 'LV_EPI', 'RV_ENDO', 'RV_EPI', 'BIV_EPI'];
const WHAT = 'The biventricular wall: the BIV_EPI mesh less the LV_ENDO and RV_ENDO cavities, cut at the base into one closed solid';

describe('bivWallReadiness', () => {
  it('is ready once LV_ENDO, RV_ENDO and BIV_EPI were run with the settings in the panel', () => {
    const [lv, rv, epi] = [mesh('LV_ENDO'), mesh('RV_ENDO'), mesh('BIV_EPI')];
    const r = bivWallReadiness(SURFACES, keptOf(lv, rv, epi, mesh('LV_EPI')), KEY);
    expect(r.ready).toBe(true);
    if (!r.ready) return;
    expect([r.lvEndo, r.rvEndo, r.bivEpi]).toEqual([lv, rv, epi]);
    expect(r.lvEndo).toBe(lv);
    expect(r.title).toBe(`${WHAT} (their last runs, with these parameters); regions epicardium, lv_endocardium, rv_endocardium, base; wall thickness per vertex (mm)`);
    // Another mesh of any of the three is another wall; the LV wall's key is another matter.
    const again = bivWallReadiness(SURFACES, keptOf(lv, mesh('RV_ENDO', KEY, 5), epi), KEY);
    expect(again.ready && again.key !== r.key).toBe(true);
  });

  it('says which surfaces the file lacks, and that BIV_EPI needs LV_EPI and RV_EPI curves', () => {
    expect(bivWallReadiness(null, keptOf(), KEY)).toEqual({ ready: false, key: '', title: `${WHAT}: open a file with LV_ENDO, RV_ENDO, LV_EPI and RV_EPI contours` });
    // An LV-only file (LV_ENDO, LV_EPI): no RV cavity, and no RV_EPI to join into BIV_EPI.
    expect(bivWallReadiness(['LV_ENDO', 'LV_EPI'], keptOf(mesh('LV_ENDO')), KEY).title).toBe(
      `${WHAT}: this file has no RV_ENDO contours; BIV_EPI needs LV_EPI and RV_EPI curves, and this file has no RV_EPI`,
    );
    // Both endocardia but no epicardium at all.
    expect(bivWallReadiness(['LV_ENDO', 'RV_ENDO'], keptOf(), KEY).title).toBe(`${WHAT}: BIV_EPI needs LV_EPI and RV_EPI curves, and this file has no LV_EPI and no RV_EPI`);
    expect(bivWallReadiness(['RV_EPI', 'LV_EPI', 'BIV_EPI'], keptOf(), KEY).title).toBe(`${WHAT}: this file has no LV_ENDO and no RV_ENDO contours`);
    // LV_EPI and RV_EPI there but no BIV_EPI listed: a core that does not join them.
    expect(bivWallReadiness(['LV_ENDO', 'RV_ENDO', 'LV_EPI', 'RV_EPI'], keptOf(), KEY).title).toBe(`${WHAT}: this core does not join LV_EPI and RV_EPI into BIV_EPI`);
  });

  it('says which to run, and how to get BIV_EPI run (All leaves it out unless it is the current surface)', () => {
    const viaBiv = '(pick BiV epicardium in the Surface menu, then All: All leaves it out unless it is the current surface)';
    expect(bivWallReadiness(SURFACES, keptOf(mesh('LV_EPI')), KEY).title).toBe(`${WHAT}: run LV_ENDO, RV_ENDO and BIV_EPI first ${viaBiv}`);
    expect(bivWallReadiness(SURFACES, keptOf(mesh('LV_ENDO')), KEY).title).toBe(`${WHAT}: run RV_ENDO and BIV_EPI too ${viaBiv}`);
    expect(bivWallReadiness(SURFACES, keptOf(mesh('LV_ENDO'), mesh('RV_ENDO')), KEY).title).toBe(`${WHAT}: run BIV_EPI too (pick BiV epicardium in the Surface menu)`);
    // BIV_EPI run: the others are run by All as any surface.
    expect(bivWallReadiness(SURFACES, keptOf(mesh('BIV_EPI')), KEY).title).toBe(`${WHAT}: run LV_ENDO and RV_ENDO too (Surface menu, or All)`);
  });

  it('says which meshes are of other parameters', () => {
    const other = settingsKey({ iterations: 250, beta: 0.2 }, 'auto', DEFAULT_OPTIONS);
    const stale = bivWallReadiness(SURFACES, keptOf(mesh('LV_ENDO'), mesh('RV_ENDO', other), mesh('BIV_EPI')), KEY);
    expect(stale).toEqual({ ready: false, key: '', title: `${WHAT}: RV_ENDO was last run with other parameters; run it again with these (Surface menu, or All)` });
    expect(bivWallReadiness(SURFACES, keptOf(mesh('LV_ENDO'), mesh('RV_ENDO'), mesh('BIV_EPI', other)), KEY).title).toBe(
      `${WHAT}: BIV_EPI was last run with other parameters; run it again with these (pick BiV epicardium in the Surface menu)`,
    );
    // The settings changed after all three runs: none is of them.
    expect(bivWallReadiness(SURFACES, keptOf(mesh('LV_ENDO'), mesh('RV_ENDO'), mesh('BIV_EPI')), other).title).toBe(
      `${WHAT}: LV_ENDO, RV_ENDO and BIV_EPI were last run with other parameters; run them again with these (pick BiV epicardium in the Surface menu, then All: All leaves it out unless it is the current surface)`,
    );
  });

  it('matches the file\'s names whatever their case', () => {
    const r = bivWallReadiness(['lv_endo', 'Rv_Endo', 'lv_epi', 'rv_epi', 'BIV_EPI'], keptOf(mesh('lv_endo'), mesh('Rv_Endo'), mesh('BIV_EPI')), KEY);
    expect(r.ready && [r.lvEndo.surface, r.rvEndo.surface, r.bivEpi.surface]).toEqual(['lv_endo', 'Rv_Endo', 'BIV_EPI']);
  });
});

describe('the biventricular wall file', () => {
  it('is named after the input like the surface exports, with BiV_wall for the surface', () => {
    expect(bivWallFileName(info, 'obj')).toBe('patient1-ED-BiV_wall.obj');
    expect(bivWallFileName({ ...info, fileName: 'seg.nii.gz', frame: '9' }, 'vtk')).toBe('seg-BiV_wall-frame9.vtk');
  });

  it('carries the app version, the input and its three surfaces in the command line\'s order, the settings and the minimum thickness', () => {
    const lines = bivWallHeaderLines(info, 'LV_ENDO', 'BIV_EPI', 'RV_ENDO', WALL_MIN_THICKNESS_MM);
    expect(lines[0]).toBe('heartmesh 0.1.0 (core 0.1.0), units: mm');
    expect(lines[1]).toBe('input: patient1-ED.csv surface: LV_ENDO + BIV_EPI + RV_ENDO');
    expect(lines[2]).toMatch(/^lids: auto iterations=250 beta=0\.1 smoothing_method=laplacian-affine /);
    expect(lines[3]).toBe('min_thickness=1 mm (endocardial vertices closer to the epicardium or to the other cavity moved away from it)');
    expect(bivWallHeaderLines(info, 'LV_ENDO', 'BIV_EPI', 'RV_ENDO', null)[3]).toBe('min_thickness=off');
  });

  it('names the four regions each format carries', () => {
    expect(bivWallFormatTitle('stl')).toMatch(/^Biventricular wall as binary STL.*STL has no place for the regions/);
    expect(bivWallFormatTitle('obj')).toMatch(/g epicardium, g lv_endocardium, g rv_endocardium, g base/);
    expect(bivWallFormatTitle('ply')).toMatch(/face property region \(1 epicardium, 2 lv_endocardium, 3 rv_endocardium, 4 base\)/);
    expect(bivWallFormatTitle('vtk')).toMatch(/cell data region \(1 epicardium, 2 lv_endocardium, 3 rv_endocardium, 4 base\), point data thickness \(mm\)/);
  });
});

describe('the biventricular figures line', () => {
  it('gives patient 1 ED\'s wall, mass, both cavities and mean thickness, then the vertices moved (the CLI\'s notes)', () => {
    expect(bivWallFiguresText(summary)).toBe(
      'Wall 132.5 ml · mass 139.1 g · LV cavity 135.0 ml · RV cavity 127.0 ml · thickness 5.3 mm mean. Volumes below the base. ' +
        '18 vertices of the endocardia moved up to 1.45 mm under the epicardium and apart from the other cavity, ' +
        '1 vertex of the epicardium up to 0.25 mm out over the endocardia, to keep the wall at least 1 mm thick',
    );
    const title = bivWallFiguresTitle(summary);
    expect(title).toContain('LV_ENDO + BIV_EPI + RV_ENDO: 2140 vertices, 4276 triangles, closed');
    expect(title).toContain('regions (triangles): 1 epicardium 1253, 2 lv_endocardium 1495, 3 rv_endocardium 1302, 4 base 226');
    expect(title).toContain('thickness min 1.0, median 5.5, max 12.4 mm');
    expect(title).toContain('mass = 1.05 g/ml x wall volume');
  });

  it('warns of crossings by pair of regions, as the command line does', () => {
    const still = { ...summary, endocardium_moved: { ...summary.endocardium_moved, vertices: 0 }, epicardium_moved: { ...summary.epicardium_moved, vertices: 0 } };
    expect(bivWallFiguresText(still)).toBe('Wall 132.5 ml · mass 139.1 g · LV cavity 135.0 ml · RV cavity 127.0 ml · thickness 5.3 mm mean. Volumes below the base');
    const crossing: WallSummary = {
      ...still,
      endo_epi_crossings: 7,
      crossings: [
        { regions: ['epicardium', 'rv_endocardium'], pairs: 4 },
        { regions: ['lv_endocardium', 'rv_endocardium'], pairs: 2 },
        { regions: ['rv_endocardium', 'rv_endocardium'], pairs: 1 },
      ],
    };
    expect(bivWallFiguresText(crossing)).toBe(
      'Wall 132.5 ml · mass 139.1 g · LV cavity 135.0 ml · RV cavity 127.0 ml · thickness 5.3 mm mean. Volumes below the base. ' +
        '⚠ the rv endocardium passes through the epicardium (4 crossing triangle pairs), the rv endocardium passes through the lv endocardium (2 crossing triangle pairs), ' +
        'the rv endocardium passes through itself (1 crossing triangle pairs): volume meshers will refuse it',
    );
    // A core without the pairs: the total.
    expect(bivWallFiguresText({ ...crossing, crossings: undefined })).toMatch(/\. ⚠ the surfaces pass through each other \(7 crossing triangle pairs\): volume meshers will refuse it$/);
  });

  it('passes on the core\'s notes (a base moved towards the apex, a fold left out), each a sentence', () => {
    const still = { ...summary, endocardium_moved: { ...summary.endocardium_moved, vertices: 0 }, epicardium_moved: { ...summary.epicardium_moved, vertices: 0 } };
    const noted: WallSummary = {
      ...still,
      notes: ['the base was moved 1 mm towards the apex: at the plane given, the base plane cuts the RV endocardium in 2 outlines, not one'],
    };
    expect(bivWallFiguresText(noted)).toBe(
      'Wall 132.5 ml · mass 139.1 g · LV cavity 135.0 ml · RV cavity 127.0 ml · thickness 5.3 mm mean. Volumes below the base. ' +
        'The base was moved 1 mm towards the apex: at the plane given, the base plane cuts the RV endocardium in 2 outlines, not one',
    );
  });

  it('says why a wall was not built', () => {
    expect(bivWallErrorText('the biventricular wall: degenerate input: the base plane does not cut the epicardium')).toBe(
      '⚠ The biventricular wall could not be built: degenerate input: the base plane does not cut the epicardium',
    );
    expect(bivWallErrorText('the worker crashed earlier')).toBe('⚠ The biventricular wall could not be built: the worker crashed earlier');
  });
});

describe('the export panel\'s biventricular wall', () => {
  useFakeDocument();
  beforeEach(() => {
    saved.length = 0;
  });

  type Build = (f: WallFormat) => Promise<{ summary: WallSummary; bytes: Uint8Array }> | null;
  function panel(bivWallFile: Build) {
    const failed: unknown[] = [];
    const asked: WallFormat[] = [];
    const p = new ExportPanel(
      exportSource(info, {
        bivWallFile: (f) => {
          asked.push(f);
          return bivWallFile(f);
        },
        failed: (e) => failed.push(e),
      }),
    );
    const root = p.element as unknown as FakeElement;
    return { p, root, buttons: formatButtons(root, 'biv-wall'), lvButtons: formatButtons(root, 'wall'), failed, asked, figures: root.byTestId('biv-wall-figures')! };
  }
  const all = (s: string) => mesh(s);
  const ready = () => bivWallReadiness(SURFACES, all, KEY);
  const settle = () => new Promise((r) => setTimeout(r, 0));

  it('is a row of its own under the LV wall, disabled, saying why, until the wall can be built', () => {
    const { p, buttons, lvButtons, root } = panel(() => null);
    const rows = root.children.filter((c): c is FakeElement => typeof c !== 'string' && (c.dataset.testid ?? '').endsWith('wall-export'));
    expect(rows.map((r) => r.dataset.testid)).toEqual(['wall-export', 'biv-wall-export']);
    expect(buttons.map((b) => b.disabled)).toEqual([true, true, true, true]);
    expect(buttons[0].title).toBe(`${WHAT}: open a file with LV_ENDO, RV_ENDO, LV_EPI and RV_EPI contours`);
    expect(buttons[2].getAttribute('aria-label')).toBe('Biventricular wall PLY');
    p.setBivWall(bivWallReadiness(SURFACES, (s) => (s === 'BIV_EPI' ? undefined : mesh(s)), KEY));
    expect(buttons.map((b) => b.disabled)).toEqual([true, true, true, true]);
    expect(buttons[1].title).toMatch(/run BIV_EPI too/);
    expect(root.byTestId('biv-wall-export')!.dataset.ready).toBe('0');
    p.setBivWall(ready());
    expect(buttons.map((b) => b.disabled)).toEqual([false, false, false, false]);
    expect(buttons[1].title).toBe(bivWallFormatTitle('obj'));
    expect(root.byTestId('biv-wall-export')!.dataset.ready).toBe('1');
    // The LV row is its own: still greyed.
    expect(lvButtons.map((b) => b.disabled)).toEqual([true, true, true, true]);
    p.setWall(wallReadiness(SURFACES, all, KEY));
    expect(lvButtons.map((b) => b.disabled)).toEqual([false, false, false, false]);
  });

  it('builds, saves <base>-BiV_wall.<ext> and shows the figures, which go when the meshes change', async () => {
    const bytes = new TextEncoder().encode('# heartmesh 0.1.0\n');
    let resolve!: (v: { summary: WallSummary; bytes: Uint8Array }) => void;
    const { p, buttons, figures, asked, root } = panel(() => new Promise((r) => (resolve = r)));
    p.setBivWall(ready());
    buttons[1].fire('click');
    expect(asked).toEqual(['obj']);
    expect(buttons.every((b) => b.disabled)).toBe(true);
    expect(figures.dataset.state).toBe('busy');
    expect(figures.textContent).toBe('building the biventricular wall…');
    resolve({ summary, bytes });
    await settle();
    expect(saved.map((s) => [s.name, s.type])).toEqual([['patient1-ED-BiV_wall.obj', 'model/obj']]);
    expect(saved[0].data).toEqual(bytes);
    expect(figures.dataset.state).toBe('done');
    expect(figures.textContent).toBe(bivWallFiguresText(summary));
    expect(figures.title).toBe(bivWallFiguresTitle(summary));
    expect(Number(figures.dataset.wallMl)).toBe(132.47267309576594);
    expect(Number(figures.dataset.massG)).toBe(139.09630675055425);
    expect(Number(figures.dataset.lvCavityMl)).toBe(135.0049193600555);
    expect(Number(figures.dataset.rvCavityMl)).toBe(127.01773160942558);
    expect(figures.dataset.crossings).toBe('0');
    expect(figures.dataset.triangles).toBe('4276');
    expect(figures.classList.contains('warn')).toBe(false);
    // The LV row's figures line is untouched.
    expect(root.byTestId('wall-figures')!.hidden).toBe(true);
    expect(buttons.every((b) => !b.disabled)).toBe(true);
    p.setBivWall(ready());
    expect(figures.hidden).toBe(false);
    // Another BIV_EPI mesh: the figures go, and so do their numbers.
    p.setBivWall(bivWallReadiness(SURFACES, (s) => mesh(s, KEY, s === 'BIV_EPI' ? 6 : 4), KEY));
    expect(figures.hidden).toBe(true);
    expect(figures.dataset.state).toBeUndefined();
    expect(figures.dataset.rvCavityMl).toBeUndefined();
  });

  it('shows why a wall could not be built, reports it, and stays usable', async () => {
    let fail = true;
    const error = { code: 'degenerate', message: 'the biventricular wall: degenerate input: the base plane does not cut the epicardium' };
    const { p, buttons, figures, failed } = panel(() => (fail ? Promise.reject(error) : Promise.resolve({ summary, bytes: new Uint8Array(3) })));
    p.setBivWall(ready());
    buttons[3].fire('click');
    await settle();
    expect(saved).toHaveLength(0);
    expect(figures.dataset.state).toBe('error');
    expect(figures.textContent).toBe('⚠ The biventricular wall could not be built: degenerate input: the base plane does not cut the epicardium');
    expect(figures.classList.contains('warn')).toBe(true);
    expect(failed).toEqual([error]);
    expect(buttons.every((b) => !b.disabled)).toBe(true);
    fail = false;
    buttons[0].fire('click');
    await settle();
    expect(saved.map((s) => s.name)).toEqual(['patient1-ED-BiV_wall.stl']);
    expect(figures.dataset.state).toBe('done');
    expect(figures.classList.contains('warn')).toBe(false);
  });

  it('a wall with crossings is shown as a warning', async () => {
    const crossing = { ...summary, endo_epi_crossings: 2, crossings: [{ regions: ['epicardium', 'lv_endocardium'] as [string, string], pairs: 2 }] };
    const { p, buttons, figures } = panel(() => Promise.resolve({ summary: crossing, bytes: new Uint8Array(3) }));
    p.setBivWall(ready());
    buttons[0].fire('click');
    await settle();
    expect(figures.classList.contains('warn')).toBe(true);
    expect(figures.dataset.crossings).toBe('2');
    expect(figures.textContent).toMatch(/⚠ the lv endocardium passes through the epicardium \(2 crossing triangle pairs\): volume meshers will refuse it$/);
  });
});
