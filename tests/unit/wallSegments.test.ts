// The LV wall's AHA segments in the app: the Segments CSV (the wall file's `#` header, a line on
// how the segments were placed, one row per segment, a segment without wall left empty, not 0),
// the two files' names, the caption and the note; and on the fake DOM, the bullseye under the LV
// wall's figures: shown once a wall is built (by an export or by View) with its caption and its
// two buttons, which save the core's SVG text as it is and the CSV; the note alone when the core
// placed no segments; taken away exactly when the figures are (a rebuild under way, a parameter
// changed, a failed build); never under the biventricular wall. The SVG's import into the page
// (DOMParser, real DOM) is the e2e test's: here it is a stand-in that records what it was given
// (bullseyeFixtures.ts, shared with thickening.test.ts).
import { afterEach, beforeEach, describe, expect, it, vi } from 'vitest';
import type { WallFormat, WallSegments, WallSummary } from '../../web/src/core-client/protocol';
import { DEFAULT_OPTIONS } from '../../web/src/core-client/protocol';
import { settingsKey } from '../../web/src/app/keptSurfaces';
import { wallHeaderLines, wallReadiness, type WallMesh } from '../../web/src/io/export/wall';
import { bivWallReadiness } from '../../web/src/io/export/bivWall';
import {
  SEGMENTS_CSV_COLUMNS, bullseyeFileName, noSegmentsText, segmentsCaption, segmentsCsvFileName, segmentsHeaderLine, writeSegmentsCsv,
} from '../../web/src/io/export/segments';
import type { ExportInfo } from '../../web/src/io/export/header';
import { AHA_NAMES, BULLSEYE_SVG, svgStandIn } from './bullseyeFixtures';
import { FakeElement, fakeDocument } from './fakeDom';
import { exportSource } from './panelHarness';

const saved: { data: unknown; name: string; type: string }[] = [];
vi.mock('../../web/src/io/download', () => ({
  download: (data: unknown, name: string, type: string) => saved.push({ data, name, type }),
}));
vi.mock('../../web/src/io/svgImport', () => import('./bullseyeFixtures').then((f) => ({ importSvg: f.svgStandIn.importSvg })));
const { ExportPanel } = await import('../../web/src/io/ExportPanel');

/** Patient 1 ED's placement (the CLI's report), its figures made up but for segments 2 and 6. */
const segments: WallSegments = {
  septum_from: "the RV contours' centre (934)",
  septum_direction: [-0.85, -0.51, -0.15],
  anterior_direction: [0.22, -0.6, 0.77],
  axis: [-0.48, 0.62, 0.62],
  level_depths_mm: [0, 25.868268292658385, 51.73653658531677, 77.60480487797516, 81.75009375581506],
  segments: AHA_NAMES.map((name, i) => ({ id: i + 1, name, mean_mm: 6 + i / 10, min_mm: 4 + i / 10, max_mm: 9 + i / 10, area_mm2: 1500 + i })),
};
segments.segments[1] = { id: 2, name: 'basal anteroseptal', mean_mm: 12.3213017485221, min_mm: 7.785080985713122, max_mm: 15.590515923974527, area_mm2: 1936.8696364159487 };
segments.segments[5] = { id: 6, name: 'basal anterolateral', mean_mm: 6.0004305280187715, min_mm: 4.75290240694907, max_mm: 7.770895966420188, area_mm2: 2030.7932034436194 };


const base: WallSummary = {
  surfaces: { endo: 'LV_ENDO', epi: 'LV_EPI' }, format: 'ply', vertices: 1557, triangles: 3110,
  wall_volume_ml: 99.54830215721525, myocardial_mass_g: 104.52571726507601, density_g_per_ml: 1.05, cavity_volume_ml: 135.0049193600555,
  thickness_mm: { mean: 7.111881237391894, median: 6.69, p95: 12.29, min: 2.8, max: 15.59, count: 1557 },
  regions: [{ id: 1, name: 'epicardium', triangles: 1475 }, { id: 2, name: 'endocardium', triangles: 1495 }, { id: 3, name: 'base', triangles: 140 }],
  endo_epi_crossings: 0, folded_edges: 0,
  endocardium_moved: { min_thickness_mm: 1, vertices: 0, max_mm: 0 }, epicardium_moved: { min_thickness_mm: 1, vertices: 0, max_mm: 0 },
  base_plane: { origin: [0, 0, 0], normal: [0, 0, 1] },
};
const withSegments: WallSummary = { ...base, segments, bullseye_svg: BULLSEYE_SVG };
const NOTE = 'the file has no RV_INSERT landmarks and no RV contours to place the septum by';
const withoutSegments: WallSummary = { ...base, segments: null, segments_note: NOTE };

const info: ExportInfo = {
  appVersion: '0.1.0', coreVersion: '0.1.0', fileName: 'patient1-ED.csv', surface: 'LV_EPI', frame: null,
  lids: 'auto', options: { ...DEFAULT_OPTIONS }, params: { iterations: 250, beta: 0.1 },
};

describe('the Segments CSV', () => {
  it('has the wall file\'s header, how the segments were placed, the columns and one row per segment', () => {
    const csv = writeSegmentsCsv(withSegments, info)!;
    const lines = csv.split('\n');
    const header = wallHeaderLines(info, 'LV_ENDO', 'LV_EPI', 1);
    expect(lines.slice(0, header.length)).toEqual(header.map((l) => `# ${l}`));
    expect(lines[1]).toBe('# input: patient1-ED.csv surface: LV_ENDO + LV_EPI');
    expect(lines[header.length]).toBe("# segments: AHA 17, septum from the RV contours' centre (934); level borders 0.0, 25.9, 51.7, 77.6, 81.8 mm below the base");
    expect(lines[header.length + 1]).toBe(SEGMENTS_CSV_COLUMNS);
    expect(SEGMENTS_CSV_COLUMNS).toBe('segment,name,mean_mm,min_mm,max_mm,area_mm2');
    const rows = lines.slice(header.length + 2);
    expect(rows.at(-1)).toBe('');
    expect(rows).toHaveLength(18);
    expect(rows[1]).toBe('2,basal anteroseptal,12.3213,7.7851,15.5905,1936.87');
    expect(rows[5]).toBe('6,basal anterolateral,6.0004,4.7529,7.7709,2030.79');
    expect(rows[16]).toBe('17,apex,7.6000,5.6000,10.6000,1516.00');
    expect(rows.slice(0, 17).map((r) => Number(r.split(',')[0]))).toEqual(AHA_NAMES.map((_, i) => i + 1));
  });

  it('leaves a segment without wall empty (missing, not 0), quotes a name with a comma, and is null without segments', () => {
    const odd = structuredClone(segments);
    odd.segments[16] = { id: 17, name: 'apex, cap', mean_mm: null, min_mm: null, max_mm: null, area_mm2: 0 };
    const csv = writeSegmentsCsv({ ...withSegments, segments: odd }, info)!;
    expect(csv.split('\n').at(-2)).toBe('17,"apex, cap",,,,0.00');
    expect(writeSegmentsCsv(withoutSegments, info)).toBeNull();
    expect(writeSegmentsCsv(base, info)).toBeNull();
    // No minimum thickness asked for: the header says so, as the wall file's does.
    const off = { ...withSegments, endocardium_moved: { min_thickness_mm: null, vertices: 0, max_mm: 0 } };
    expect(writeSegmentsCsv(off, info)!.split('\n')[3]).toBe('# min_thickness=off');
  });

  it('names the files after the wall\'s (its frame after it), and says where the septum came from', () => {
    expect(bullseyeFileName(info)).toBe('patient1-ED-LV_wall-segments.svg');
    expect(segmentsCsvFileName(info)).toBe('patient1-ED-LV_wall-segments.csv');
    expect(segmentsCsvFileName({ ...info, fileName: 'seg.nii.gz', frame: '9' })).toBe('seg-LV_wall-frame9-segments.csv');
    expect(segmentsCaption(segments)).toBe("Septum placed from the RV contours' centre (934 points)");
    expect(segmentsCaption({ ...segments, septum_from: 'RV_INSERT landmarks (10)' })).toBe('Septum placed from RV_INSERT landmarks (10 points)');
    expect(segmentsHeaderLine(segments)).toMatch(/^segments: AHA 17, septum from /);
    expect(noSegmentsText(NOTE)).toBe(`No AHA segments: ${NOTE}`);
    expect(noSegmentsText(undefined)).toBe('No AHA segments for this wall');
  });
});

describe('the bullseye under the LV wall\'s figures', () => {
  beforeEach(() => {
    vi.stubGlobal('document', fakeDocument);
    saved.length = 0;
    svgStandIn.reset();
  });
  afterEach(() => vi.unstubAllGlobals());

  const KEY = settingsKey({ iterations: 250, beta: 0.1 }, 'auto', DEFAULT_OPTIONS);
  const mesh = (surface: string): WallMesh => ({ surface, positions: new Float32Array(12), indices: new Uint32Array([0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2]), settings: KEY });
  const ready = (settings = KEY) => wallReadiness(['LV_ENDO', 'LV_EPI'], mesh, settings);
  const settle = () => new Promise((r) => setTimeout(r, 0));
  type Reply = () => Promise<{ summary: WallSummary; bytes: Uint8Array }>;

  function panel(lv: Reply, biv: Reply = () => Promise.resolve({ summary: base, bytes: new Uint8Array(1) })) {
    const p = new ExportPanel(
      exportSource(info, {
        wallFile: (_f: WallFormat) => lv(),
        bivWallFile: (_f: WallFormat) => biv(),
      }),
    );
    const root = p.element as unknown as FakeElement;
    const get = (id: string) => root.byTestId(id)!;
    return {
      p, root,
      click: (id: string) => get(id).fire('click'),
      segments: get('wall-segments'),
      figure: get('wall-bullseye'),
      drawing: get('wall-bullseye-svg'),
      caption: get('wall-bullseye-caption'),
      note: get('wall-segments-note'),
      figures: get('wall-figures'),
      svgButton: get('export-wall-bullseye'),
      csvButton: get('export-wall-segments'),
    };
  }
  /** The buttons' row (their parent) is shown. */
  const buttonsShown = (b: FakeElement) => !b.parentElement!.hidden;

  it('is hidden until a wall is built; an export shows the bullseye, its caption and the buttons, which save the SVG as it is and the CSV', async () => {
    const t = panel(() => Promise.resolve({ summary: withSegments, bytes: new Uint8Array(3) }));
    expect(t.segments.hidden).toBe(true);
    t.p.setWall(ready());
    expect(t.segments.hidden).toBe(true);
    t.click('export-wall-obj');
    expect(t.segments.hidden).toBe(true); // building: the figures line says so, nothing under it
    await settle();
    expect(t.figures.dataset.state).toBe('done');
    expect(t.segments.hidden).toBe(false);
    expect(t.segments.dataset.state).toBe('segments');
    expect(svgStandIn.imported).toEqual([{ text: BULLSEYE_SVG, prefix: 'wall-bullseye' }]);
    expect(t.drawing.children).toHaveLength(1);
    expect((t.drawing.children[0] as FakeElement).dataset.from).toBe(BULLSEYE_SVG);
    expect(t.drawing.hidden).toBe(false);
    expect(t.figure.hidden).toBe(false);
    expect(t.caption.textContent).toBe(segmentsCaption(segments));
    expect(t.figure.title).toMatch(/anterior up, septum left/);
    expect(t.note.hidden).toBe(true);
    expect(buttonsShown(t.svgButton)).toBe(true);
    expect(t.svgButton.textContent).toBe('Bullseye SVG');
    expect(t.csvButton.textContent).toBe('Segments CSV');

    saved.length = 0;
    t.click('export-wall-bullseye');
    t.click('export-wall-segments');
    expect(saved.map((s) => [s.name, s.type])).toEqual([
      ['patient1-ED-LV_wall-segments.svg', 'image/svg+xml'],
      ['patient1-ED-LV_wall-segments.csv', 'text/csv'],
    ]);
    expect(saved[0].data).toBe(BULLSEYE_SVG);
    expect(saved[1].data).toBe(writeSegmentsCsv(withSegments, info));
  });

  it('goes when the figures go: a rebuild under way, a parameter changed; stays for the same meshes', async () => {
    let resolve!: (v: { summary: WallSummary; bytes: Uint8Array }) => void;
    const t = panel(() => new Promise((r) => (resolve = r)));
    t.p.setWall(ready());
    t.click('export-wall-ply');
    resolve({ summary: withSegments, bytes: new Uint8Array(3) });
    await settle();
    expect(t.segments.hidden).toBe(false);
    // The same meshes again (another surface's run): it stays.
    t.p.setWall(ready());
    expect(t.segments.hidden).toBe(false);
    // Another export: busy, then the new wall's.
    t.click('export-wall-stl');
    expect(t.figures.dataset.state).toBe('busy');
    expect(t.segments.hidden).toBe(true);
    resolve({ summary: withSegments, bytes: new Uint8Array(3) });
    await settle();
    expect(t.segments.hidden).toBe(false);
    // Parameters changed: the figures and the bullseye go together, the drawing with them.
    t.p.setWall(ready('other'));
    expect(t.figures.hidden).toBe(true);
    expect(t.segments.hidden).toBe(true);
    expect(t.segments.dataset.state).toBeUndefined();
    expect(t.drawing.children).toHaveLength(0);
    expect(t.caption.textContent).toBe('');
    // Nothing left to save.
    saved.length = 0;
    t.click('export-wall-bullseye');
    t.click('export-wall-segments');
    expect(saved).toEqual([]);
  });

  it('View fills it as an export does, and a failed build takes it away', async () => {
    let fail = false;
    const t = panel(() => (fail ? Promise.reject({ code: 'degenerate', message: 'the LV wall: no' }) : Promise.resolve({ summary: withSegments, bytes: new Uint8Array(3) })));
    t.p.setWall(ready());
    t.click('view-wall');
    await settle();
    expect(t.figures.dataset.state).toBe('done');
    expect(t.segments.hidden).toBe(false);
    expect(t.caption.textContent).toBe(segmentsCaption(segments));
    fail = true;
    t.click('export-wall-vtk');
    await settle();
    expect(t.figures.dataset.state).toBe('error');
    expect(t.segments.hidden).toBe(true);
  });

  it('says why there are no segments instead, without the bullseye or its buttons', async () => {
    const t = panel(() => Promise.resolve({ summary: withoutSegments, bytes: new Uint8Array(3) }));
    t.p.setWall(ready());
    t.click('export-wall-obj');
    await settle();
    expect(t.segments.hidden).toBe(false);
    expect(t.segments.dataset.state).toBe('note');
    expect(t.note.hidden).toBe(false);
    expect(t.note.textContent).toBe(`No AHA segments: ${NOTE}`);
    expect(t.figure.hidden).toBe(true);
    expect(buttonsShown(t.svgButton)).toBe(false);
    expect(svgStandIn.imported).toEqual([]);
    // A summary of an older core, without the field: nothing at all.
    const old = panel(() => Promise.resolve({ summary: base, bytes: new Uint8Array(3) }));
    old.p.setWall(ready());
    old.click('export-wall-obj');
    await settle();
    expect(old.figures.dataset.state).toBe('done');
    expect(old.segments.hidden).toBe(true);
  });

  it('a bullseye that cannot be imported leaves the caption saying so and the files still saved', async () => {
    svgStandIn.refuse = true;
    const t = panel(() => Promise.resolve({ summary: withSegments, bytes: new Uint8Array(3) }));
    t.p.setWall(ready());
    t.click('export-wall-obj');
    await settle();
    expect(t.drawing.hidden).toBe(true);
    expect(t.caption.textContent).toMatch(/\(the bullseye could not be drawn here; Bullseye SVG saves it\)$/);
    saved.length = 0;
    t.click('export-wall-bullseye');
    expect(saved.map((s) => s.data)).toEqual([BULLSEYE_SVG]);
  });

  it('is the LV wall\'s only: the biventricular wall has none', async () => {
    const t = panel(() => Promise.resolve({ summary: withSegments, bytes: new Uint8Array(3) }));
    t.p.setBivWall(bivWallReadiness(['LV_ENDO', 'RV_ENDO', 'BIV_EPI'], mesh, KEY));
    t.click('export-biv-wall-obj');
    await settle();
    const biv = t.root.byTestId('biv-wall-export')!;
    expect(biv.findAll((e) => e.dataset.testid === 'wall-segments')).toEqual([]);
    expect(t.root.findAll((e) => e.dataset.testid === 'wall-segments')).toHaveLength(1);
    expect(t.segments.hidden).toBe(true);
  });
});
