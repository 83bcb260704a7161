// What the tests of the app's two AHA bullseyes share (wallSegments.test.ts, the LV wall's under
// its figures; thickening.test.ts, the systolic thickening in the Function panel): the segments'
// names as the core gives them, an SVG of the core's drawing's shape, and a stand-in for its import
// into the page. The real import (svgImport.ts) wants DOMParser, a real DOM, so it is the e2e
// tests'; on the fake DOM the stand-in records what it was given and can refuse.
import { FakeElement } from './fakeDom';

/** The 17 AHA segments' names in the core's order (segment i + 1 at i). */
export const AHA_NAMES = [
  'basal anterior', 'basal anteroseptal', 'basal inferoseptal', 'basal inferior', 'basal inferolateral', 'basal anterolateral',
  'mid anterior', 'mid anteroseptal', 'mid inferoseptal', 'mid inferior', 'mid inferolateral', 'mid anterolateral',
  'apical anterior', 'apical septal', 'apical inferior', 'apical lateral', 'apex',
];

/** A bullseye SVG as the core sends it (its size, a trailing newline): what the views import and save. */
export const BULLSEYE_SVG = '<svg xmlns="http://www.w3.org/2000/svg" width="460" height="530" viewBox="0 0 460 530"><rect width="460" height="530" fill="#ffffff"/></svg>\n';

/**
 * The stand-in for svgImport.ts's `importSvg`: an `svg` element carrying the text it was given
 * (`data-from`), or null while `refuse` (a text that is not an SVG). A test file mocks the module
 * with it itself, since vi.mock is hoisted in the file that calls it, and resets it before each test:
 *
 *     vi.mock('../../web/src/io/svgImport', () => import('./bullseyeFixtures').then((f) => ({ importSvg: f.svgStandIn.importSvg })));
 */
export const svgStandIn = {
  /** What it was given, in order. */
  imported: [] as { text: string; prefix: string }[],
  refuse: false,
  importSvg: (text: string, prefix: string): FakeElement | null => {
    svgStandIn.imported.push({ text, prefix });
    if (svgStandIn.refuse) return null;
    const svg = new FakeElement('svg');
    svg.setAttribute('data-from', text);
    return svg;
  },
  reset: (): void => {
    svgStandIn.imported.length = 0;
    svgStandIn.refuse = false;
  },
};
