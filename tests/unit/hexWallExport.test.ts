// The LV wall as hexahedra in the Export panel: the pure parts (the layout and layers typed, checked
// against the core's ranges; the cells a layout has; the file name after the LV wall's; the header;
// the figures line and its warning; the title saying why it cannot be built, after the LV wall's;
// the core's refusal as a sentence, and which failures are refusals), then the row on the fake
// DOM: greyed, saying why, until the LV wall can be built; then it asks the core about the smallest
// mesh once per set of meshes and, refused, shows the core's reason with no Save, or, accepted,
// Save builds the layout and layers typed, downloads `<file>-LV_wall-hex-<R>x<K>x<L>.vtk` and
// fills the figures, which an edit or other meshes take away; a Save the core refuses is said on
// the figures line and the banner.
import { describe, expect, it, vi } from 'vitest';
import type { HexSummary } from '../../web/src/core-client/protocol';
import { DEFAULT_OPTIONS } from '../../web/src/core-client/protocol';
import { settingsKey } from '../../web/src/app/keptSurfaces';
import {
  HEX_DEFAULT_LAYERS, HEX_HINT, HEX_PROBE, checkHex, hexCounts, hexErrorText, hexFigures, hexFiguresText, hexFiguresTitle, hexFileName, hexHeaderLines, hexReason,
  hexSaveTitle, hexTitle, isHexRefusal, type HexLayout,
} from '../../web/src/io/export/hexWall';
import { wallReadiness, type WallMesh } from '../../web/src/io/export/wall';
import { headerLines, type ExportInfo } from '../../web/src/io/export/header';
import type { BuiltHex } from '../../web/src/io/HexRow';
import type { FakeElement } from './fakeDom';
import { exportSource, useFakeDocument } from './panelHarness';

const saved: { name: string; type: string }[] = [];
vi.mock('../../web/src/io/download', () => ({ download: (_data: unknown, name: string, type: string) => saved.push({ name, type }) }));
const { ExportPanel } = await import('../../web/src/io/ExportPanel');

const info: ExportInfo = {
  appVersion: '0.1.0', coreVersion: '0.1.0', fileName: 'patient1-ED.csv', surface: 'LV_ENDO', frame: null,
  lids: 'auto', options: { ...DEFAULT_OPTIONS }, params: { iterations: 250 },
};

/** `heartmesh myocardium patient1-ED.csv --hex-mesh hex.vtk` (the report's hex_mesh, without its file). */
const SUMMARY: HexSummary = {
  rings: 24, points_per_ring: 48, layers: 3, points: 4612, hexahedra: 3312, wedges: 144,
  volume_ml: 99.14603267576106, layouts_volume_ml: 99.14294559005285, min_scaled_jacobian: 0.07931420472423663, inverted_cells: 0, helix_deg: [60, -60], endocardium_moved: 0,
};
const NO_SEPTUM = 'the hexahedral wall: its cells are laid out from the septum: the file has no RV_INSERT landmarks and no RV contours';

describe('the layout and layers typed', () => {
  it('takes whole numbers in the core\'s ranges (2-200 rings, 8-720 points, 1-20 layers), spaces around them', () => {
    expect(checkHex('24', '48', '3')).toEqual({ ok: true, layout: { rings: 24, points: 48, layers: 3 } });
    expect(checkHex(' 10 ', '16', ' 2')).toEqual({ ok: true, layout: { rings: 10, points: 16, layers: 2 } });
    expect(checkHex('2', '8', '1')).toEqual({ ok: true, layout: HEX_PROBE });
    expect(checkHex('200', '720', '20')).toEqual({ ok: true, layout: { rings: 200, points: 720, layers: 20 } });
  });

  it('says which number is wrong and the range it must be in', () => {
    expect(checkHex('24', '48', '0')).toEqual({ ok: false, message: 'Layers: a whole number from 1 to 20' });
    expect(checkHex('24', '48', '21')).toEqual({ ok: false, message: 'Layers: a whole number from 1 to 20' });
    expect(checkHex('1', '48', '3')).toEqual({ ok: false, message: 'Rings: a whole number from 2 to 200' });
    expect(checkHex('24', '7', '3')).toEqual({ ok: false, message: 'Points per ring: a whole number from 8 to 720' });
    expect(checkHex('1', '48', '')).toEqual({ ok: false, message: 'Rings: a whole number from 2 to 200; Layers: a whole number from 1 to 20' });
    for (const bad of ['', '2.5', '1e1', '-3', '3x', 'abc', '0x3']) expect(checkHex('24', '48', bad).ok, JSON.stringify(bad)).toBe(false);
  });

  it('counts the cells and points the core builds: a wedge per point round the apex, a hexahedron per quad above, per layer', () => {
    expect(hexCounts({ rings: 24, points: 48, layers: 3 })).toEqual({ hexahedra: 3312, wedges: 144, points: 4612 });
    expect(hexCounts({ rings: 24, points: 48, layers: 2 })).toEqual({ hexahedra: 2208, wedges: 96, points: 3 * (24 * 48 + 1) });
    expect(hexCounts({ rings: 10, points: 16, layers: 2 })).toEqual({ hexahedra: 288, wedges: 32, points: 483 });
    expect(hexSaveTitle({ rings: 24, points: 48, layers: 1 })).toMatch(/^Save 1104 hexahedra \+ 48 wedges \(24 rings x 48 points, 1 layer\) as a VTK unstructured grid/);
  });
});

describe('the hexahedra\'s file, figures and words', () => {
  it('is named after the LV wall\'s file, the layout and layers after it', () => {
    expect(hexFileName(info, { rings: 24, points: 48, layers: 3 })).toBe('patient1-ED-LV_wall-hex-24x48x3.vtk');
    expect(hexFileName({ ...info, fileName: 'GPFile_000.txt', frame: '9' }, { rings: 10, points: 16, layers: 2 })).toBe('GPFile_000-LV_wall-frame9-hex-10x16x2.vtk');
    expect(hexFileName({ ...info, fileName: 'my heart.csv', surface: null }, { rings: 24, points: 48, layers: 20 })).toBe('my_heart-LV_wall-hex-24x48x20.vtk');
  });

  it('carries the exports\' header lines, naming both surfaces', () => {
    const lines = hexHeaderLines(info, 'LV_ENDO', 'LV_EPI');
    expect(lines).toEqual(headerLines({ ...info, surface: 'LV_ENDO + LV_EPI' }));
    expect(lines[1]).toBe('input: patient1-ED.csv surface: LV_ENDO + LV_EPI');
  });

  it('says the cells, the points, the volume and the worst corner; a warning for inverted cells', () => {
    expect(hexFiguresText(SUMMARY)).toBe('3312 hexahedra + 144 wedges · 4612 points · 99.1 ml · min scaled Jacobian 0.08');
    expect(hexFiguresText({ ...SUMMARY, volume_ml: 100.04, min_scaled_jacobian: 0.0504 })).toBe('3312 hexahedra + 144 wedges · 4612 points · 100.0 ml · min scaled Jacobian 0.05');
    expect(hexFigures(SUMMARY).notes).toEqual([]);
    expect(hexFigures({ ...SUMMARY, inverted_cells: 1, min_scaled_jacobian: -0.2 })).toEqual({
      figures: ['3312 hexahedra + 144 wedges', '4612 points', '99.1 ml', 'min scaled Jacobian -0.20'],
      notes: ['⚠ 1 inverted cell: the endo- and epicardium cross or touch there, a solver would refuse it (try Align breath-holds)'],
    });
    expect(hexFiguresText({ ...SUMMARY, inverted_cells: 7 })).toMatch(/ · min scaled Jacobian 0\.08\. ⚠ 7 inverted cells: .* refuse them/);
    const title = hexFiguresTitle(SUMMARY);
    expect(title.split('\n')).toHaveLength(4);
    expect(title).toMatch(/^24 rings x 48 points per surface, 3 layers through the wall: 3312 hexahedra, 144 wedges round the apex, 4612 points\n/);
    expect(title).toContain('volume 99.1 ml in the cells, 99.1 ml between the two layouts\' surfaces');
    expect(title).toContain('smallest scaled Jacobian 0.079');
  });

  it('says why it cannot be built in the LV wall\'s words, with its own subject', () => {
    const run = (endo: boolean, epi: boolean, settings = 'k') => wallReadiness(['LV_ENDO', 'LV_EPI'], (s) => ((s === 'LV_ENDO' ? endo : epi) ? mesh(s, 'k') : undefined), settings);
    expect(hexTitle(run(true, false))).toMatch(/^The LV wall as layers of hexahedra .*: run LV_EPI too \(Surface menu, or All\)$/);
    expect(hexTitle(run(true, true, 'other'))).toMatch(/^The LV wall as layers of hexahedra .*: LV_ENDO and LV_EPI were last run with other parameters;/);
    expect(hexTitle(wallReadiness(null, () => undefined, ''))).toMatch(/: open a file with LV_ENDO and LV_EPI contours$/);
    expect(hexTitle(run(true, true))).toMatch(/^The LV wall as layers of hexahedra .*\(the LV wall's meshes, their last runs with these parameters\)$/);
    expect(hexTitle({ ready: false, title: 'something else' })).toBe('something else');
  });

  it('gives the core\'s reason in its words, without the prefix the row already says', () => {
    expect(hexReason(NO_SEPTUM)).toBe('Its cells are laid out from the septum: the file has no RV_INSERT landmarks and no RV contours');
    expect(hexErrorText('the hexahedral wall: parameter layers: 1-20 layers through the wall (got 0)')).toBe('⚠ The hexahedra could not be built: Parameter layers: 1-20 layers through the wall (got 0)');
  });

  it('takes only the core\'s answers for refusals, not a worker restarted or a file not loaded', () => {
    expect(isHexRefusal({ code: 'degenerate', message: NO_SEPTUM })).toBe(true);
    expect(isHexRefusal({ code: 'hex_unavailable', message: 'this core cannot build the hexahedral wall' })).toBe(true);
    expect(isHexRefusal({ code: 'worker_crashed', message: 'the worker crashed earlier' })).toBe(false);
    expect(isHexRefusal({ code: 'not_loaded', message: 'p1.csv has not been loaded' })).toBe(false);
  });
});

const KEY = settingsKey({ iterations: 250 }, 'auto', DEFAULT_OPTIONS);

function mesh(surface: string, settings = KEY): WallMesh {
  return { surface, positions: new Float32Array(12).fill(1.5), indices: new Uint32Array([0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2]), settings };
}
const ready = (settings = KEY) => wallReadiness(['LV_ENDO', 'LV_EPI'], (s) => mesh(s, settings), settings);
const endoOnly = () => wallReadiness(['LV_ENDO', 'LV_EPI'], (s) => (s === 'LV_ENDO' ? mesh(s) : undefined), KEY);

type Control = FakeElement & { disabled: boolean; value: string };

/** The panel with a recording hexahedra source: each build asked for (`RxKxL`, `+header`) and each failure reported. */
function panel(answer: (layout: HexLayout, header: boolean) => Promise<BuiltHex> | null = () => Promise.resolve({ summary: SUMMARY, bytes: new Uint8Array([1]) })) {
  const asked: string[] = [];
  const failed: unknown[] = [];
  const p = new ExportPanel(
    exportSource(info, {
      hexFile: (l, header) => (asked.push(`${l.rings}x${l.points}x${l.layers}${header ? '+header' : ''}`), answer(l, header)),
      failed: (e) => void failed.push(e),
    }),
  );
  const root = p.element as unknown as FakeElement;
  const get = (testid: string) => root.byTestId(testid) as Control;
  return {
    p, root, asked, failed,
    row: get('hex-export'), save: get('export-hex'), rings: get('hex-rings'), points: get('hex-points'), layers: get('hex-layers'),
    reason: get('hex-reason'), figures: get('hex-figures'), inputError: get('hex-input-error'),
    type(input: Control, value: string) {
      input.value = value;
      input.fire('input');
    },
  };
}
const settle = () => new Promise((r) => setTimeout(r, 0));

describe('the hexahedra row', () => {
  useFakeDocument();

  it('sits directly under the LV wall\'s row, says what it is for, and is greyed with the LV wall\'s reason until the wall can be built', () => {
    const t = panel();
    const rows = t.root.children as unknown as FakeElement[];
    const at = (id: string) => rows.findIndex((c) => c.dataset?.testid === id);
    expect(at('hex-export')).toBe(at('wall-export') + 1);
    expect(t.row.textContent).toContain(HEX_HINT);
    expect(t.save.textContent).toBe('Hexahedra VTK');
    expect([t.rings.value, t.points.value, t.layers.value]).toEqual(['24', '48', String(HEX_DEFAULT_LAYERS)]);
    expect([t.save.disabled, t.layers.disabled, t.row.dataset.state]).toEqual([true, true, 'none']);
    expect(t.save.title).toMatch(/: open a file with LV_ENDO and LV_EPI contours$/);
    t.p.setWall(endoOnly());
    expect(t.save.disabled).toBe(true);
    expect(t.save.title).toMatch(/^The LV wall as layers of hexahedra .*: run LV_EPI too \(Surface menu, or All\)$/);
    expect(t.asked).toEqual([]);
  });

  it('once the wall can be built: the smallest mesh asked for once per set of meshes; accepted, Save builds the numbers typed, saves them, fills the figures', async () => {
    const t = panel();
    t.p.setWall(ready());
    t.p.setWall(ready());
    expect(t.asked).toEqual(['2x8x1']);
    expect([t.row.dataset.state, t.save.disabled]).toEqual(['checking', true]);
    await settle();
    expect([t.row.dataset.state, t.save.disabled, t.reason.hidden]).toEqual(['ready', false, true]);
    expect(t.save.title).toMatch(/^Save 3312 hexahedra \+ 144 wedges \(24 rings x 48 points, 3 layers\)/);

    t.type(t.layers, '2');
    t.save.fire('click');
    expect(t.figures.dataset.state).toBe('busy');
    expect(t.figures.textContent).toBe('building the hexahedra…');
    expect(t.save.disabled).toBe(true);
    await settle();
    expect(t.asked.at(-1)).toBe('24x48x2+header');
    expect(saved.at(-1)).toEqual({ name: 'patient1-ED-LV_wall-hex-24x48x2.vtk', type: 'application/octet-stream' });
    expect(t.figures.dataset.state).toBe('done');
    expect(t.figures.textContent).toBe('3312 hexahedra + 144 wedges · 4612 points · 99.1 ml · min scaled Jacobian 0.08');
    expect(t.figures.classList.contains('warn')).toBe(false);
    expect([t.figures.dataset.hexahedra, t.figures.dataset.wedges, t.figures.dataset.points, t.figures.dataset.inverted]).toEqual(['3312', '144', '4612', '0']);
    expect(t.figures.title).toBe(hexFiguresTitle(SUMMARY));

    // Another number typed: the figures (of the last mesh) go; the same meshes again: they stay; other meshes: they go, and the core is asked again.
    t.type(t.rings, '10');
    expect(t.figures.hidden).toBe(true);
    t.save.fire('click');
    await settle();
    expect(t.asked.at(-1)).toBe('10x48x2+header');
    t.p.setWall(ready());
    expect(t.figures.hidden).toBe(false);
    t.p.setWall(ready(settingsKey({ iterations: 300 }, 'auto', DEFAULT_OPTIONS)));
    expect(t.figures.hidden).toBe(true);
    expect(t.asked.at(-1)).toBe('2x8x1');
    // Stale meshes: greyed again, with the LV wall's reason.
    t.p.setWall(wallReadiness(['LV_ENDO', 'LV_EPI'], (s) => mesh(s), 'other'));
    expect([t.row.dataset.state, t.save.disabled]).toEqual(['none', true]);
    expect(t.save.title).toMatch(/were last run with other parameters/);
  });

  it('inverted cells: the figures line in the warning style, saying so', async () => {
    const t = panel(() => Promise.resolve({ summary: { ...SUMMARY, inverted_cells: 3, min_scaled_jacobian: -0.12 }, bytes: new Uint8Array(1) }));
    t.p.setWall(ready());
    await settle();
    t.save.fire('click');
    await settle();
    expect(t.figures.classList.contains('warn')).toBe(true);
    expect(t.figures.textContent).toMatch(/^3312 hexahedra \+ 144 wedges · 4612 points · 99\.1 ml · min scaled Jacobian -0\.12\. ⚠ 3 inverted cells: /);
  });

  it('numbers out of range: no Save, the range said; no call', async () => {
    const t = panel();
    t.p.setWall(ready());
    await settle();
    t.type(t.layers, '0');
    expect([t.save.disabled, t.inputError.hidden, t.inputError.textContent]).toEqual([true, false, 'Layers: a whole number from 1 to 20']);
    expect(t.save.title).toBe('Layers: a whole number from 1 to 20');
    t.save.fire('click');
    await settle();
    expect(t.asked).toEqual(['2x8x1']);
    t.type(t.layers, '20');
    expect([t.save.disabled, t.inputError.hidden]).toEqual([false, true]);
  });

  it('a file without RV landmarks or contours: the core\'s reason greyed in place of the form, no Save, no banner', async () => {
    const t = panel(() => Promise.reject({ code: 'degenerate', message: NO_SEPTUM }));
    t.p.setWall(ready());
    await settle();
    expect(t.row.dataset.state).toBe('refused');
    expect([t.reason.hidden, t.reason.textContent]).toEqual([false, 'Its cells are laid out from the septum: the file has no RV_INSERT landmarks and no RV contours']);
    expect(t.row.title).toBe(t.reason.textContent);
    expect(t.save.parentElement?.hidden).toBe(true);
    expect(t.inputError.hidden).toBe(true);
    expect(t.failed).toEqual([]);
  });

  it('a probe answered after its meshes were replaced is ignored; a worker restarted under it does not grey the row', async () => {
    let reject: (e: unknown) => void = () => undefined;
    let calls = 0;
    const t = panel(() => (++calls === 1 ? new Promise((_, r) => (reject = r)) : Promise.reject({ code: 'worker_crashed', message: 'the worker crashed' })));
    t.p.setWall(ready());
    t.p.setWall(ready(settingsKey({ iterations: 300 }, 'auto', DEFAULT_OPTIONS)));
    reject({ code: 'degenerate', message: NO_SEPTUM });
    await settle();
    expect(t.row.dataset.state).toBe('ready');
    expect(t.reason.hidden).toBe(true);
  });

  it('a Save the core refuses says why on the figures line and the banner; the row stays usable', async () => {
    let n = 0;
    const t = panel(() => (n++ === 0 ? Promise.resolve({ summary: SUMMARY, bytes: new Uint8Array(0) }) : Promise.reject({ code: 'degenerate', message: 'the hexahedral wall: the epicardium: the surface has no part below its base plane' })));
    t.p.setWall(ready());
    await settle();
    const before = saved.length;
    t.save.fire('click');
    await settle();
    expect(saved.length).toBe(before);
    expect(t.figures.dataset.state).toBe('error');
    expect(t.figures.textContent).toBe('⚠ The hexahedra could not be built: The epicardium: the surface has no part below its base plane');
    expect(t.figures.classList.contains('warn')).toBe(true);
    expect(t.failed).toHaveLength(1);
    expect(t.save.disabled).toBe(false);
  });
});
