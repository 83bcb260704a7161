// A GPFile holding two time frames of one heart, built in the test from biv-me patient 1's
// GPFile_000.txt (end-diastole, frame 0) and GPFile_009.txt (end-systole, frame 9), so no fixture
// is committed. Every row gets its file's frame in the `time frame` column: both files label
// slice 8 "1.0" (a quirk of the example, which the core reads as that slice's own frame), and
// left so it would be a third frame holding one slice of each phase. The core reads frame 0 by
// default; frame 9 is exactly GPFile_009.txt. Used by tests/e2e/frames.test.mjs and
// tests/node/frames.test.ts.
//
// Also the same patient's phases written as text, as exports often write them: patient1-ED.csv's
// rows labelled `ED` and patient1-ES.csv's labelled `ES` in a `phase` column of one CSV (every ES
// contour has an ED namesake, so the file is a sequence and ED is read by default; frame ES is
// exactly patient1-ES.csv).

export const TWO_FRAMES_NAME = 'GPFile_000-009.txt';
/** The frames the file holds, in file order. */
export const FRAMES = ['0', '9'];

/** The rows of a GPFile (after its header) with the time frame (7th column) set to `frame`. */
function rowsInFrame(text, frame) {
  return text
    .split(/\r?\n/)
    .slice(1)
    .filter((row) => row.trim() !== '')
    .map((row) => {
      const f = row.split('\t');
      if (f.length < 7) throw new Error(`a GPFile row without a time frame: ${row}`);
      f[6] = frame;
      return f.join('\t');
    });
}

/** The two-frame GPFile text from the texts of GPFile_000.txt and GPFile_009.txt. */
export function twoFrameGpFile(ed, es) {
  const header = ed.split(/\r?\n/)[0];
  if (!/time frame/.test(header)) throw new Error(`not a GPFile header: ${header}`);
  return `${[header, ...rowsInFrame(ed, FRAMES[0]), ...rowsInFrame(es, FRAMES[1])].join('\n')}\n`;
}

export const PHASES_NAME = 'patient1-ED-ES.csv';
/** The phases `phasesCsv` labels, in file order. */
export const PHASES = ['ED', 'ES'];

/** The ED/ES CSV text from the texts of patient1-ED.csv and patient1-ES.csv (canonical CSV, header first). */
export function phasesCsv(ed, es) {
  const header = ed.split(/\r?\n/)[0];
  if (header !== 'contour,x,y,z,surface') throw new Error(`not a canonical contour CSV header: ${header}`);
  const rows = (text, phase) => text.split(/\r?\n/).slice(1).filter((row) => row.trim() !== '').map((row) => `${row},${phase}`);
  return `${[`${header},phase`, ...rows(ed, PHASES[0]), ...rows(es, PHASES[1])].join('\n')}\n`;
}
