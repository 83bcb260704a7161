// The bundled examples (web/src/io/samples.ts): every button's file is credited in
// public/samples/NOTICE.md; each id is distinct; each has a short name; the segmentation example
// opens on the LV epicardium. (The label map's content: tests/node/labelMap.test.ts.)
import { describe, expect, it } from 'vitest';
import notice from '../../public/samples/NOTICE.md?raw';
import { findSample, SAMPLES } from '../../web/src/io/samples';

describe('bundled examples', () => {
  it('each is credited, with a distinct id, and a short name for a crowded top bar', () => {
    for (const s of SAMPLES) expect(notice, s.file).toContain(`\`${s.file}\``);
    expect(new Set(SAMPLES.map((s) => s.id)).size).toBe(SAMPLES.length);
    // Four full names and three pickers overran the privacy badge at 1280 px (tests/e2e/frames.test.mjs).
    expect(SAMPLES.map((s) => s.short)).toEqual(['P1 · ED', 'P1 · ES', 'P2 · ED', 'NIfTI']);
    expect(SAMPLES.reduce((n, s) => n + s.short.length, 0)).toBeLessThan(SAMPLES.reduce((n, s) => n + s.label.length, 0) / 2);
  });

  it('the segmentation example: a compressed NIfTI label map, opened on the LV epicardium', () => {
    const s = findSample('spasm-seg');
    expect(s).toMatchObject({ file: 'cardiomesh-spasm-seg.nii.gz', surface: 'LV_EPI', label: 'Segmentation · NIfTI' });
    expect(s?.description).toMatch(/label map/);
    expect(SAMPLES.map((x) => x.id)).toEqual(['patient1-ED', 'patient1-ES', 'patient2-ED', 'spasm-seg']);
  });
});
