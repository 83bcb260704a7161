// Which short-axis stack each long-axis view opened with it goes to (web/src/io/studyGroups.ts):
// the stack whose name shares the most tokens with the view's, the first on a tie.
import { describe, expect, it } from 'vitest';
import {
  addedViewsText, assignViews, byName, groupStudies, isSingleSlice, isStack, mergeViews, nameTokens, sharedTokens,
} from '../../web/src/io/studyGroups';

describe('study groups', () => {
  it('name tokens: split on non-alphanumerics, lower case, the extension left out', () => {
    expect([...nameTokens('001_LA_ED_gt.nii.gz')]).toEqual(['001', 'la', 'ed', 'gt']);
    expect([...nameTokens('seg4_la_4ch.nii')]).toEqual(['seg4', 'la', '4ch']);
    expect([...nameTokens('Patient 7 - SAX.NII.GZ')]).toEqual(['patient', '7', 'sax']);
    expect(sharedTokens('001_LA_ED_gt.nii.gz', '001_SA_ED_gt.nii.gz')).toBe(3);
    expect(sharedTokens('001_LA_ED_gt.nii.gz', '001_SA_ES_gt.nii.gz')).toBe(2);
    // NRRD and DICOM SEG files alike (3D Slicer's .seg.nrrd, a PACS's .dcm).
    expect([...nameTokens('seg_lax1.seg.nrrd')]).toEqual(['seg', 'lax1']);
    expect([...nameTokens('sa_ED.nrrd')]).toEqual(['sa', 'ed']);
    expect([...nameTokens('LA_2CH_seg.dcm')]).toEqual(['la', '2ch', 'seg']);
    expect(sharedTokens('p7_LA_ED.dcm', 'p7_SA_ED.nii.gz')).toBe(2);
  });

  it('M&Ms-2: the ED view with the ED stack, the ES view with the ES stack, whatever the order', () => {
    const stacks = ['001_SA_ES_gt.nii.gz', '001_SA_ED_gt.nii.gz'];
    const views = ['001_LA_ED_gt.nii.gz', '001_LA_ES_gt.nii.gz'];
    expect(groupStudies(stacks, views)).toEqual({
      studies: [
        { stack: '001_SA_ES_gt.nii.gz', views: ['001_LA_ES_gt.nii.gz'] },
        { stack: '001_SA_ED_gt.nii.gz', views: ['001_LA_ED_gt.nii.gz'] },
      ],
      loose: [],
    });
    // Two subjects in one drop: each view with its own subject's phase.
    const two = groupStudies(
      ['001_SA_ED_gt.nii.gz', '002_SA_ED_gt.nii.gz', '002_SA_ES_gt.nii.gz'],
      ['002_LA_ES_gt.nii.gz', '001_LA_ED_gt.nii.gz', '002_LA_ED_gt.nii.gz'],
    );
    expect(two.studies.map((s) => s.views)).toEqual([['001_LA_ED_gt.nii.gz'], ['002_LA_ED_gt.nii.gz'], ['002_LA_ES_gt.nii.gz']]);
  });

  it('UK Biobank: the 2-, 3- and 4-chamber views with seg_sa, the only stack (no token shared)', () => {
    const g = groupStudies(['seg_sa.nii.gz'], ['seg4_la_2ch.nii.gz', 'seg4_la_3ch.nii.gz', 'seg4_la_4ch.nii.gz']);
    expect(g).toEqual({ studies: [{ stack: 'seg_sa.nii.gz', views: ['seg4_la_2ch.nii.gz', 'seg4_la_3ch.nii.gz', 'seg4_la_4ch.nii.gz'] }], loose: [] });
    // The CLI's names: SEG.nii.gz and SEG_lax1..3.nii.gz.
    expect(assignViews(['other.nii.gz', 'seg.nii.gz'], ['seg_lax1.nii.gz', 'seg_lax3.nii.gz'])).toEqual([1, 1]);
  });

  it('ties go to the first stack; views without a stack are loose', () => {
    // Both stacks share "patient1" with the view: the first takes it.
    expect(assignViews(['patient1_sa_a.nii', 'patient1_sa_b.nii'], ['patient1_la.nii'])).toEqual([0]);
    expect(assignViews(['b_sa.nii', 'a_sa.nii'], ['x_la.nii'])).toEqual([0]);
    expect(groupStudies([], ['seg4_la_4ch.nii.gz', 'seg4_la_2ch.nii.gz'])).toEqual({ studies: [], loose: ['seg4_la_4ch.nii.gz', 'seg4_la_2ch.nii.gz'] });
    expect(groupStudies(['seg_sa.nii.gz'], [])).toEqual({ studies: [{ stack: 'seg_sa.nii.gz', views: [] }], loose: [] });
  });

  it('views added onto a stack: one of the same name replaces the older; all in name order', () => {
    const older = [{ name: 'b.nii', v: 1 }, { name: 'd.nii', v: 1 }];
    expect(mergeViews(older, [{ name: 'c.nii', v: 2 }, { name: 'b.nii', v: 2 }, { name: 'a.nii', v: 2 }]).map((x) => `${x.name}${x.v}`)).toEqual(['a.nii2', 'b.nii2', 'c.nii2', 'd.nii1']);
    expect(older).toEqual([{ name: 'b.nii', v: 1 }, { name: 'd.nii', v: 1 }]);
    expect(byName([{ name: 'seg_lax10.nii' }, { name: 'seg_lax2.nii' }, { name: 'seg_lax1.nii' }]).map((x) => x.name)).toEqual(['seg_lax1.nii', 'seg_lax2.nii', 'seg_lax10.nii']);
    expect(addedViewsText(['seg4_la_4ch.nii.gz'], 'seg_sa.nii.gz')).toBe('seg4_la_4ch.nii.gz added to seg_sa.nii.gz as a long-axis view.');
    expect(addedViewsText(['a.nii', 'b.nii'], 's.nii')).toBe('a.nii, b.nii added to s.nii as long-axis views.');
  });

  it('a single slice (a dimension of 1) is a view; every dimension over 1 a stack; no grid neither', () => {
    expect(isSingleSlice({ dims: [102, 88, 1], frames: 1 })).toBe(true);
    expect(isSingleSlice({ dims: [1, 88, 102], frames: 30 })).toBe(true);
    expect(isStack({ dims: [102, 88, 1], frames: 1 })).toBe(false);
    expect(isStack({ dims: [100, 108, 10], frames: 30 })).toBe(true);
    expect(isSingleSlice(null) || isStack(null)).toBe(false);
  });
});
