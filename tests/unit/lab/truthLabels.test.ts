// The Lab's surface labels (web/src/lab/truthLabels.ts): guessed from mesh file names, checked as
// the CLI checks them, refused when another truth has them, and the truth a surface is compared
// with picked as the core picks it (never another surface's).
import { describe, expect, it } from 'vitest';
import { guessLabel, isLabel, labelProblem, labelsForNew, simulateProblem, truthForSurface } from '../../../web/src/lab/truthLabels';
import { shortName } from '../../../web/src/lab/TruthList';

describe('surface labels of truth meshes', () => {
  it('are guessed from the known surface names in a file name, in any case', () => {
    expect(guessLabel('bivme-patient1-ED-RV_ENDO-closed.obj')).toBe('RV_ENDO');
    expect(guessLabel('bivme-patient1-ED-LV_ENDO-closed.obj')).toBe('LV_ENDO');
    expect(guessLabel('cardiomesh-spasm-LV_epi.obj')).toBe('LV_EPI');
    expect(guessLabel('cardiomesh-spasm-RV_endo.obj')).toBe('RV_ENDO');
    expect(guessLabel('case7_biv-epi.stl')).toBe('BIV_EPI');
    expect(guessLabel('/data/heart/rvepi.vtp')).toBe('RV_EPI');
    expect(guessLabel('LV_Endocardium.ply')).toBe('LV_ENDO');
    // No known name (or one inside a longer word): asked for.
    expect(guessLabel('bivme-patient1-ED-EPI-closed.obj')).toBeNull();
    expect(guessLabel('sphere.obj')).toBeNull();
    expect(guessLabel('solvendo.obj')).toBeNull();
    expect(guessLabel('cardiomesh-LV-myocardium.obj')).toBeNull();
  });

  it('follow the CLI rule and are refused when another truth has them', () => {
    expect(isLabel('LV_ENDO') && isLabel('rv-cavity_2') && isLabel('x'.repeat(64))).toBe(true);
    expect(isLabel('') || isLabel('LV ENDO') || isLabel('LV,ENDO') || isLabel('x'.repeat(65)) || isLabel('é')).toBe(false);
    const labels = ['LV_ENDO', 'RV_ENDO', null];
    expect(labelProblem('lv_endo', 2, labels)).toBe("the label lv_endo is already truth 1's: give each truth its own");
    expect(labelProblem('RV_ENDO', 1, labels)).toBeNull();
    expect(labelProblem('BIV_EPI', 2, labels)).toBeNull();
    expect(labelProblem('LV ENDO', 2, labels)).toMatch(/is no surface label/);
  });

  it('of files joining the truths: the guess unless taken (by a truth held or a file before it)', () => {
    const names = ['a-LV_ENDO.obj', 'b-lv_endo.obj', 'c-RV_ENDO.obj', 'sphere.obj'];
    expect(labelsForNew(names, [])).toEqual([
      { label: 'LV_ENDO', clash: null },
      { label: null, clash: 'LV_ENDO' },
      { label: 'RV_ENDO', clash: null },
      { label: null, clash: null },
    ]);
    expect(labelsForNew(['x-RV_ENDO.obj'], ['rv_endo'])).toEqual([{ label: null, clash: 'RV_ENDO' }]);
  });

  it('are needed to simulate several truths, not one', () => {
    expect(simulateProblem([{ name: 'a.obj', label: null }])).toBeNull();
    expect(simulateProblem([{ name: 'a.obj', label: 'LV_ENDO' }, { name: 'b.obj', label: 'RV_ENDO' }])).toBeNull();
    expect(simulateProblem([{ name: 'a.obj', label: 'LV_ENDO' }, { name: 'b.obj', label: null }])).toBe('give each truth a surface label (LV_ENDO, RV_ENDO, …): b.obj has none');
  });

  it('pick the truth of the reconstructed surface, and none for a surface without one', () => {
    const labels = ['LV_ENDO', 'RV_ENDO'];
    expect(truthForSurface('RV_ENDO', labels)).toBe(1);
    expect(truthForSurface('lv_endo', labels)).toBe(0);
    expect(truthForSurface('LV_EPI', labels)).toBeNull();
    expect(truthForSurface(null, labels)).toBeNull();
    // A lone truth: its file has no surface column, whatever it is called.
    expect(truthForSurface(null, [null])).toBe(0);
    expect(truthForSurface('LV_EPI', ['LV_ENDO'])).toBe(0);
  });

  it('file names are cut in the middle, where meshes of one heart differ at the end', () => {
    expect(shortName('bivme-patient1-ED-RV_ENDO-closed.obj')).toBe('bivme…RV_ENDO-closed.obj');
    expect(shortName('sphere.obj')).toBe('sphere.obj');
    expect(shortName('bivme-patient1-ED-RV_ENDO-closed.obj').length).toBe(24);
  });
});
