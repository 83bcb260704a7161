// The cvi42 fixture's frames on screen (tests/e2e/cvi42.test.mjs, zip.test.mjs): its workspace
// holds frames 0 and 9 of biv-me patient 1, LV_ENDO 441 contour points at 0 and 269 at 9.
import assert from 'node:assert/strict';
import { meshOnScreen, runAndWait } from './lib.mjs';

const PICKER = '[data-testid=frame-picker]';

/**
 * With frame 0 on screen (`zero`: its figures), checks the picker offers 0 and 9, picks 9 (the
 * images read again) and checks its run: LV_ENDO as `heartmesh info --frame 9` counts it, closed,
 * smaller (systole). Returns frame 9's figures.
 */
export async function pickFrameNine(page, zero) {
  assert.deepEqual(await page.$$eval(`${PICKER} option`, (os) => os.map((o) => o.value)), ['0', '9']);
  assert.equal(await page.inputValue(PICKER), '0');
  await runAndWait(page, () => page.selectOption(PICKER, '9'));
  const nine = await meshOnScreen(page);
  assert.equal(nine.contourPoints, 269, 'frame 9: LV_ENDO as `heartmesh info --frame 9` counts it');
  assert.equal(nine.watertight, true);
  assert.ok(nine.volumeMl < zero.volumeMl, `frame 9 is systole: ${nine.volumeMl.toFixed(1)} < ${zero.volumeMl.toFixed(1)} ml`);
  return nine;
}
