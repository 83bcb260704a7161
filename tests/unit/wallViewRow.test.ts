// The walls' View toggle in the export panel (fake DOM): enabled exactly when the row's export
// buttons are, with their titles; pressed, it builds the wall as PLY (or takes the build the row
// holds for the same meshes: no second request) and hands it to the view with the figures filled
// as after an export; pressed again, or the wall going stale, or the panel told a new run began,
// takes it away (once); one wall at a time; a failure says why and leaves nothing shown.
import { afterEach, beforeEach, describe, expect, it, vi } from 'vitest';
import type { WallFormat, WallSummary } from '../../web/src/core-client/protocol';
import { DEFAULT_OPTIONS } from '../../web/src/core-client/protocol';
import { settingsKey } from '../../web/src/app/keptSurfaces';
import { wallFiguresText, wallReadiness, type WallMesh } from '../../web/src/io/export/wall';
import { bivWallReadiness } from '../../web/src/io/export/bivWall';
import type { ExportInfo } from '../../web/src/io/export/header';
import type { BuiltWall } from '../../web/src/io/WallRow';
import { fakeDocument, type FakeElement } from './fakeDom';
import { exportSource } from './panelHarness';

const saved: string[] = [];
vi.mock('../../web/src/io/download', () => ({ download: (_data: unknown, name: string) => saved.push(name) }));
const { ExportPanel } = await import('../../web/src/io/ExportPanel');

const KEY = settingsKey({ iterations: 250 }, 'auto', DEFAULT_OPTIONS);
const mesh = (surface: string, settings = KEY, n = 4): WallMesh => ({
  surface, positions: new Float32Array(3 * n), indices: new Uint32Array([0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2]), settings,
});
const lvReady = (settings = KEY, n = 4) => wallReadiness(['LV_ENDO', 'LV_EPI'], (s) => mesh(s, KEY, n), settings);
const bivReady = () => bivWallReadiness(['LV_ENDO', 'RV_ENDO', 'BIV_EPI'], (s) => mesh(s), KEY);

const summary = (triangles: number): WallSummary => ({
  surfaces: { endo: 'LV_ENDO', epi: 'LV_EPI' }, format: 'ply', vertices: 1557, triangles,
  wall_volume_ml: 99.54830215721525, myocardial_mass_g: 104.52571726507601, density_g_per_ml: 1.05, cavity_volume_ml: 135.0049193600555,
  thickness_mm: { mean: 7.111881237391894, median: 6.69, p95: 12.29, min: 2.8, max: 15.59, count: 1557 },
  regions: [{ id: 1, name: 'epicardium', triangles: 1475 }, { id: 2, name: 'endocardium', triangles: 1495 }, { id: 3, name: 'base', triangles: 140 }],
  endo_epi_crossings: 0, folded_edges: 0,
  endocardium_moved: { min_thickness_mm: 1, vertices: 0, max_mm: 0 }, epicardium_moved: { min_thickness_mm: 1, vertices: 0, max_mm: 0 },
  base_plane: { origin: [0, 0, 0], normal: [0, 0, 1] },
});

const info: ExportInfo = {
  appVersion: '0.1.0', coreVersion: '0.1.0', fileName: 'patient1-ED.csv', surface: 'BIV_EPI', frame: null,
  lids: 'auto', options: { ...DEFAULT_OPTIONS }, params: { iterations: 250 },
};

type Build = (f: WallFormat) => Promise<BuiltWall> | null;
type Button = FakeElement & { disabled: boolean };

/** The panel with recording walls: each build asked for (`lv:ply`), each wall shown and each hide. */
function panel(opts: { lv?: Build; biv?: Build; show?: (id: string, w: BuiltWall) => void } = {}) {
  const asked: string[] = [];
  const shown: [string, BuiltWall][] = [];
  const failed: unknown[] = [];
  let hides = 0;
  const built = (tag: string, triangles: number) => () => Promise.resolve({ summary: summary(triangles), bytes: new TextEncoder().encode(`${tag}#${asked.length}`) });
  const lv = opts.lv ?? built('lv', 3110);
  const biv = opts.biv ?? built('biv', 4276);
  const p = new ExportPanel(
    exportSource(info, {
      wallFile: (f) => (asked.push(`lv:${f}`), lv(f)),
      bivWallFile: (f) => (asked.push(`biv:${f}`), biv(f)),
      failed: (e) => failed.push(e),
      showWall: (id, w) => {
        opts.show?.(id, w);
        shown.push([id, w]);
      },
      hideWall: () => void hides++,
    }),
  );
  const root = p.element as unknown as FakeElement;
  const get = (testid: string) => root.byTestId(testid) as Button;
  return {
    p, asked, shown, failed,
    hides: () => hides,
    view: get('view-wall'), bivView: get('view-biv-wall'),
    exportButtons: (['stl', 'obj', 'ply', 'vtk'] as const).map((f) => get(`export-wall-${f}`)),
    figures: get('wall-figures'),
  };
}
const settle = () => new Promise((r) => setTimeout(r, 0));
const pressed = (b: FakeElement) => b.getAttribute('aria-pressed');
const text = (w: BuiltWall) => new TextDecoder().decode(w.bytes);

describe('the walls\' View toggle', () => {
  beforeEach(() => {
    vi.stubGlobal('document', fakeDocument);
    saved.length = 0;
  });
  afterEach(() => vi.unstubAllGlobals());

  it('is enabled exactly when the export buttons are, with their title while it is not', () => {
    const t = panel();
    expect(t.view.disabled).toBe(true);
    expect(t.view.title).toBe(t.exportButtons[1].title);
    t.p.setWall(wallReadiness(['LV_ENDO', 'LV_EPI'], (s) => (s === 'LV_ENDO' ? mesh(s) : undefined), KEY));
    expect(t.view.disabled).toBe(true);
    expect(t.view.title).toMatch(/run LV_EPI too/);
    expect(t.view.title).toBe(t.exportButtons[3].title);
    t.p.setWall(lvReady());
    expect([t.view.disabled, ...t.exportButtons.map((b) => b.disabled)]).toEqual([false, false, false, false, false]);
    expect(t.view.title).toMatch(/^Show the LV wall in the 3D view in place of the surface/);
    expect(pressed(t.view)).toBe('false');
    expect(t.bivView.disabled).toBe(true);
  });

  it('builds the wall as PLY, shows it with its figures; pressed again hides it; again shows the same build without asking', async () => {
    const t = panel();
    t.p.setWall(lvReady());
    t.view.fire('click');
    expect(t.asked).toEqual(['lv:ply']);
    expect(t.view.disabled).toBe(true); // building
    expect(t.figures.dataset.state).toBe('busy');
    await settle();
    expect(t.shown.map(([id, w]) => [id, text(w)])).toEqual([['wall', 'lv#1']]);
    expect(pressed(t.view)).toBe('true');
    expect(t.view.disabled).toBe(false);
    expect(t.view.title).toMatch(/^Back to the reconstructed surface/);
    expect(t.figures.dataset.state).toBe('done');
    expect(t.figures.textContent).toBe(wallFiguresText(summary(3110)));
    expect(t.figures.dataset.triangles).toBe('3110');
    expect(t.figures.dataset.thicknessMaxMm).toBe('15.59');
    expect(t.p.viewing).toBe('wall');
    t.view.fire('click');
    expect(t.hides()).toBe(1);
    expect(pressed(t.view)).toBe('false');
    expect(t.p.viewing).toBeNull();
    t.view.fire('click');
    expect(t.asked).toEqual(['lv:ply']);
    expect(t.shown.map(([, w]) => text(w))).toEqual(['lv#1', 'lv#1']);
    expect(pressed(t.view)).toBe('true');
  });

  it('shows a PLY export\'s build without asking again; another format is not taken for it', async () => {
    const t = panel();
    t.p.setWall(lvReady());
    t.exportButtons[1].fire('click'); // OBJ
    await settle();
    t.exportButtons[2].fire('click'); // PLY
    await settle();
    expect(saved).toEqual(['patient1-ED-LV_wall.obj', 'patient1-ED-LV_wall.ply']);
    t.view.fire('click');
    expect(t.asked).toEqual(['lv:obj', 'lv:ply']);
    expect(t.shown.map(([, w]) => text(w))).toEqual(['lv#2']);
  });

  it('goes when the wall goes stale (other settings, other meshes), and the build held goes with it', async () => {
    const t = panel();
    t.p.setWall(lvReady());
    t.view.fire('click');
    await settle();
    // The same meshes again (another surface's run finished): it stays.
    t.p.setWall(lvReady());
    expect([pressed(t.view), t.hides()]).toEqual(['true', 0]);
    // A parameter changed: the meshes are of other settings.
    t.p.setWall(lvReady('other settings'));
    expect([pressed(t.view), t.hides(), t.view.disabled]).toEqual(['false', 1, true]);
    expect(t.figures.hidden).toBe(true);
    // Ready again with other meshes: View builds anew.
    t.p.setWall(lvReady(KEY, 5));
    t.view.fire('click');
    await settle();
    expect(t.asked).toEqual(['lv:ply', 'lv:ply']);
    expect(t.shown.map(([, w]) => text(w))).toEqual(['lv#1', 'lv#2']);
  });

  it('a new run, file or surface (the panel\'s hideWall) takes it away once; nothing to take when nothing is shown', async () => {
    const t = panel();
    t.p.setWall(lvReady());
    t.p.hideWall();
    expect(t.hides()).toBe(0);
    t.view.fire('click');
    await settle();
    t.p.hideWall();
    t.p.hideWall();
    expect(t.hides()).toBe(1);
    expect(pressed(t.view)).toBe('false');
  });

  it('one wall at a time: the biventricular wall takes the view from the LV wall', async () => {
    const t = panel();
    t.p.setWall(lvReady());
    t.p.setBivWall(bivReady());
    t.view.fire('click');
    await settle();
    t.bivView.fire('click');
    await settle();
    expect(t.asked).toEqual(['lv:ply', 'biv:ply']);
    expect(t.shown.map(([id]) => id)).toEqual(['wall', 'biv-wall']);
    expect([pressed(t.view), pressed(t.bivView)]).toEqual(['false', 'true']);
    expect(t.hides()).toBe(0); // replaced, not hidden
    expect(t.p.viewing).toBe('biv-wall');
    // The LV wall going stale now takes nothing away: the biventricular wall is on screen.
    t.p.setWall(lvReady('other settings'));
    expect([t.hides(), pressed(t.bivView)]).toEqual([0, 'true']);
  });

  it('stopped while building: the build comes back to the figures line, not to the view', async () => {
    let resolve!: (w: BuiltWall) => void;
    const t = panel({ lv: () => new Promise((r) => (resolve = r)) });
    t.p.setWall(lvReady());
    t.view.fire('click');
    t.p.hideWall();
    expect(t.hides()).toBe(0); // nothing was shown yet
    resolve({ summary: summary(3110), bytes: new Uint8Array(4) });
    await settle();
    expect(t.shown).toEqual([]);
    expect(pressed(t.view)).toBe('false');
    expect(t.figures.dataset.state).toBe('done');
  });

  it('a wall that cannot be built, or shown, says why; nothing is shown; the next View works', async () => {
    let buildFails = true;
    let showFails = false;
    const t = panel({
      lv: () =>
        buildFails
          ? Promise.reject({ code: 'degenerate', message: 'the LV wall: degenerate input: the base plane does not cut the epicardium' })
          : Promise.resolve({ summary: summary(3110), bytes: new Uint8Array(4) }),
      show: () => {
        if (showFails) throw new Error('PLY: no end_header line in the first 64 KiB');
      },
    });
    t.p.setWall(lvReady());
    t.view.fire('click');
    await settle();
    expect(t.figures.dataset.state).toBe('error');
    expect(t.figures.textContent).toBe('⚠ The LV wall could not be built: degenerate input: the base plane does not cut the epicardium');
    expect(t.failed).toHaveLength(1);
    expect([pressed(t.view), t.view.disabled, t.shown.length, t.hides()]).toEqual(['false', false, 0, 0]);
    // Built, but the view cannot show it: said the same way, the build kept for the next try.
    buildFails = false;
    showFails = true;
    t.view.fire('click');
    await settle();
    expect(t.figures.textContent).toBe('⚠ The LV wall could not be built: PLY: no end_header line in the first 64 KiB');
    expect(t.failed).toHaveLength(2);
    expect([pressed(t.view), t.shown.length]).toEqual(['false', 0]);
    showFails = false;
    t.view.fire('click');
    await settle();
    expect(t.asked).toEqual(['lv:ply', 'lv:ply']);
    expect([pressed(t.view), t.shown.length, t.figures.dataset.state]).toEqual(['true', 1, 'done']);
  });
});
