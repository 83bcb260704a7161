// Four time frames of biv-me patient 1 in one CSV (a `frame` column), built in the test from the
// bundled examples (public/samples/patient1-ED.csv and patient1-ES.csv), so no fixture is
// committed: frame 0 is ED, frames 1 and 2 are ED shrunk about its centre to 90 % and 80 % (the
// heart emptying between ED and ES), frame 3 is ES. Frame 1 holds no RV contours, so the RV has no
// volume there: a gap in its line of the Function panel's volume curve. Every contour of frames
// 1-3 has a namesake in frame 0, so the file is a sequence (frame 0 is read by default).
// Used by tests/e2e/function.test.mjs.

export const CYCLE_NAME = 'patient1-cycle.csv';
/** The frames the file holds, in file order. */
export const CYCLE_FRAMES = ['0', '1', '2', '3'];

const HEADER = 'contour,x,y,z,surface';

/** The data rows of a canonical contour CSV, split into their cells. */
function rows(text) {
  const [header, ...lines] = text.split(/\r?\n/);
  if (header !== HEADER) throw new Error(`not a canonical contour CSV header: ${header}`);
  return lines.filter((l) => l.trim() !== '').map((l) => l.split(','));
}

/** `cells` with x, y, z scaled by `k` about `centre`. */
function shrunk(cells, centre, k) {
  return cells.map(([id, ...rest]) => {
    const xyz = rest.slice(0, 3).map((v, a) => (centre[a] + k * (Number(v) - centre[a])).toFixed(4));
    return [id, ...xyz, rest[3]];
  });
}

/** The four-frame CSV text from the texts of patient1-ED.csv and patient1-ES.csv. */
export function cycleCsv(ed, es) {
  const edRows = rows(ed);
  const centre = [1, 2, 3].map((a) => edRows.reduce((sum, r) => sum + Number(r[a]), 0) / edRows.length);
  const noRv = (cells) => cells.filter((r) => !r[4].startsWith('RV_'));
  const frames = [edRows, noRv(shrunk(edRows, centre, 0.9)), shrunk(edRows, centre, 0.8), rows(es)];
  const lines = frames.flatMap((cells, f) => cells.map((r) => `${r.join(',')},${CYCLE_FRAMES[f]}`));
  return `${[`${HEADER},frame`, ...lines].join('\n')}\n`;
}
