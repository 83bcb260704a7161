// The Frame picker's rules: shown for a sequence only, its options and the value read, the frame
// named beside the file (exports), the frame to read when a file becomes current.
import { describe, expect, it } from 'vitest';
import type { LoadedFile, TimeFrames } from '../../web/src/core-client/protocol';
import { FIRST_OF_EACH, frameChoice, framePicker, frameToRead, missingFrameNote, namedFrame, sameFrame } from '../../web/src/app/timeFrames';

const file = (t: Partial<TimeFrames> | null, fileName = 'cine.txt'): LoadedFile => ({
  fileName, surfaces: ['LV_ENDO'], contours: [], points: new Float32Array(0), landmarks: [], warnings: [],
  timeFrames: t === null ? null : { frames: ['0', '9'], count: 2, read: ['0'], firsts: ['0'], chosen: false, leftOut: 1225, sequence: true, ...t },
});

describe('Frame picker', () => {
  it('lists the frames of a sequence as "frame N", the frame read chosen', () => {
    const p = framePicker(file({}));
    expect(p?.options.map((o) => [o.value, o.label, o.disabled])).toEqual([['0', 'frame 0', false], ['9', 'frame 9', false]]);
    expect(p?.value).toBe('0');
    expect(framePicker(file({ read: ['9'], chosen: true }))?.value).toBe('9');
  });

  it('names the frames the file says are end-diastole and end-systole (a Segment study)', () => {
    const p = framePicker(file({ frames: ['1', '10', '20'], count: 3, read: ['1'], firsts: ['1'], endDiastole: '1', endSystole: '10' }));
    expect(p?.options.map((o) => [o.label, o.title])).toEqual([
      ['frame 1 · ED', "the file's end-diastole"],
      ['frame 10 · ES', "the file's end-systole"],
      ['frame 20', undefined],
    ]);
    expect(framePicker(file({}))?.options.map((o) => o.label)).toEqual(['frame 0', 'frame 9']);
  });

  it('is not shown for a file of one frame, one without a frame column, or one whose slices each carry their own frame', () => {
    expect(framePicker(file(null))).toBeNull();
    expect(framePicker({ ...file(null), timeFrames: undefined })).toBeNull();
    expect(framePicker(file({ frames: ['3'], count: 1, read: ['3'], firsts: ['3'], sequence: false, leftOut: 0 }))).toBeNull();
    // biv-me's GPFile_009.txt alone: frame 9, slice 8 labelled 1.0.
    expect(framePicker(file({ frames: ['9', '1'], read: ['9', '1'], firsts: ['9', '1'], sequence: false, leftOut: 0 }))).toBeNull();
    expect(framePicker(null)).toBeNull();
  });

  it("offers each contour's first frame where contours start in different frames, also once a frame was chosen", () => {
    const own = file({ frames: ['0', '1', '9'], count: 3, read: ['0', '1'], firsts: ['0', '1'] });
    const p = framePicker(own);
    expect(p?.options[0]).toMatchObject({ value: FIRST_OF_EACH, label: 'first of each (0, 1)', disabled: false });
    expect(p?.value).toBe(FIRST_OF_EACH);
    const nine = framePicker(file({ frames: ['0', '1', '9'], count: 3, read: ['9'], firsts: ['0', '1'], chosen: true }));
    expect(nine?.options.map((o) => o.value)).toEqual([FIRST_OF_EACH, '0', '1', '9']);
    expect(nine?.value).toBe('9');
  });

  it('offers every frame listed, text and numbers alike, and says how many are not listed', () => {
    const p = framePicker(file({ frames: ['ED', 'ES', '2', '-1', '1.5'], count: 1005, read: ['ED'], firsts: ['ED'] }));
    expect(p?.options.map((o) => [o.value, o.label, o.disabled])).toEqual([
      ['ED', 'frame ED', false], ['ES', 'frame ES', false], ['2', 'frame 2', false], ['-1', 'frame -1', false], ['1.5', 'frame 1.5', false],
      ['…', '… 1000 more', true],
    ]);
    expect(p?.value).toBe('ED');
    expect(framePicker(file({ frames: ['ED', 'ES'], read: ['ES'], firsts: ['ED'], chosen: true }))?.value).toBe('ES');
  });

  it('reads picker values and links as frame labels, trimmed', () => {
    expect(frameChoice('9')).toBe('9');
    expect(frameChoice(' ES ')).toBe('ES');
    for (const v of ['1.5', '-1', 'Diastole']) expect(frameChoice(v)).toBe(v);
    for (const none of [FIRST_OF_EACH, ' ', null, 'x'.repeat(201)]) expect(frameChoice(none)).toBeNull();
  });

  it('compares frames as the core does: numbers as numbers, text trimmed and in any case', () => {
    for (const [a, b] of [['9', '9.0'], ['1', '1e0'], ['1', '+1'], ['0.5', '.5'], ['ES', 'es'], ['ES', ' Es '], ['inf', 'INF']]) expect(sameFrame(a, b), `${a} ${b}`).toBe(true);
    for (const [a, b] of [['9', '90'], ['ES', 'ED'], ['16', '0x10'], ['0', ''], ['1e999', 'inf'], ['E S', 'ES']]) expect(sameFrame(a, b), `${a} ${b}`).toBe(false);
  });
});

describe('the frame beside the file', () => {
  it('is named for a sequence or a chosen frame (a session of one), never for a file of one frame', () => {
    expect(namedFrame(file({}))).toBe('0');
    expect(namedFrame(file({ read: ['9'], chosen: true }))).toBe('9');
    expect(namedFrame(file({ frames: ['9'], count: 1, read: ['9'], firsts: ['9'], chosen: true, sequence: false, leftOut: 0 }))).toBe('9');
    expect(namedFrame(file({ frames: ['3'], count: 1, read: ['3'], firsts: ['3'], sequence: false }))).toBeNull();
    expect(namedFrame(file({ read: ['0', '1'], firsts: ['0', '1'] }))).toBeNull();
    expect(namedFrame(file(null))).toBeNull();
  });

  it('a frame asked for is read of a sequence that has it and does not hold it already', () => {
    expect(frameToRead(file({}), '9')).toBe('9');
    expect(frameToRead(file({}), '0')).toBe('0'); // the file's own first is not asked for: read frame 0 alone
    expect(frameToRead(file({ read: ['9'], chosen: true }), '9')).toBeNull();
    expect(frameToRead(file({ read: ['9'], chosen: true }), '9.0')).toBeNull();
    expect(frameToRead(file({}), '9.0')).toBe('9'); // asked as listed
    expect(frameToRead(file({}), '5')).toBeNull();
    expect(frameToRead(file({}), null)).toBeNull();
    expect(frameToRead(file({ sequence: false }), '9')).toBeNull();
    expect(missingFrameNote(file({}), '5')).toBe('frame 5 is not in cine.txt: showing frame 0');
    expect(missingFrameNote(file({}), '9')).toBeNull();
    expect(missingFrameNote(file(null), '5')).toBeNull();
  });

  it('text frames: a link in another case finds the file\'s own label; one the file lacks says so', () => {
    const phases = file({ frames: ['ED', 'ES'], read: ['ED'], firsts: ['ED'] });
    expect(frameToRead(phases, 'es')).toBe('ES');
    expect(frameToRead(file({ frames: ['ED', 'ES'], read: ['ES'], firsts: ['ED'], chosen: true }), 'es')).toBeNull();
    expect(missingFrameNote(phases, 'es')).toBeNull();
    expect(missingFrameNote(phases, 'systole')).toBe('frame systole is not in cine.txt: showing frame ED');
    expect(missingFrameNote(phases, '9')).toBe('frame 9 is not in cine.txt: showing frame ED');
    expect(namedFrame(file({ frames: ['ED', 'ES'], read: ['ES'], firsts: ['ED'], chosen: true }))).toBe('ES');
  });
});
