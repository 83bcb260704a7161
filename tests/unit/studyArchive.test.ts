// The study's anatomical meshes as one zip (io/studyArchive.ts): every file as the core wrote it
// plus anatomical_meshes.json (the report without the worker's file index), the same bytes for the
// same study; the line under the row in the CLI's words, the largest own-septum turn of the layouts
// built; the tooltip's displacement lines and notes.
import { describe, expect, it } from 'vitest';
import { strFromU8, unzipSync } from 'fflate';
import type { AnatomicalStudy, AnatomicalStudyReport } from '../../web/src/core-client/protocol';
import { STUDY_JSON, largestTurnDeg, studyArchive, studyArchiveName, studyDetails, studyLine } from '../../web/src/io/studyArchive';

function report(): AnatomicalStudyReport {
  const layout = (phase: string, surface: string, mean: number, turn: number | null) => ({ phase, surface, file: `${phase}-${surface}.vtk`, septum_turn_deg: turn, displacement_mean_mm: mean, displacement_max_mm: 2 * mean });
  return {
    format: 'vtk',
    layout: { rings: 24, points: 48 },
    septum: { phase: 'ED', surface: 'LV_ENDO', direction: [1, 0, 0], source: "the RV contours' centre (120) of phase ED" },
    displacement_from_phase: 'ED',
    layouts: [layout('ED', 'LV_ENDO', 0, 0), layout('ES', 'LV_ENDO', 12.634, 1.9022), layout('ES', 'LV_EPI', 10.37, null), { phase: 'MS', surface: 'LV_ENDO', file: null, note: 'no closed mesh of this surface in this phase' }],
    files: [
      { name: 'ED-LV_ENDO.vtk', index: 0 },
      { name: 'ES-LV_ENDO.vtk', index: 1 },
      { name: 'ES-LV_EPI.vtk', index: 2 },
    ],
  };
}

describe('the study archive', () => {
  it('zips every file and the report, the same bytes each time', () => {
    const r = report();
    const enc = (t: string) => new TextEncoder().encode(t).buffer as ArrayBuffer;
    const study: AnatomicalStudy = { report: r, files: r.files.map((f) => ({ name: f.name, bytes: enc(`# vtk ${f.name}\n`) })) };
    const zip = studyArchive(study);
    expect(studyArchive(study)).toEqual(zip);
    const out = unzipSync(zip);
    expect(Object.keys(out).sort()).toEqual(['ED-LV_ENDO.vtk', 'ES-LV_ENDO.vtk', 'ES-LV_EPI.vtk', STUDY_JSON]);
    expect(strFromU8(out['ES-LV_EPI.vtk'])).toBe('# vtk ES-LV_EPI.vtk\n');
    const json = JSON.parse(strFromU8(out[STUDY_JSON]));
    expect(json.files).toBeUndefined();
    expect(json.septum.phase).toBe('ED');
    expect(json.layouts[1].displacement_mean_mm).toBe(12.634);
    expect(studyArchiveName('phases')).toBe('phases-anatomical.zip');
  });

  it('says what was saved in the CLI\'s words', () => {
    const r = report();
    expect(largestTurnDeg(r)).toBe(1.9022);
    expect(studyLine(r)).toBe("3 files, 24x48, septum of phase ED (the RV contours' centre (120)); each phase's own within 1.9 degrees");
    const none = { ...r, layouts: r.layouts.map((l) => ({ ...l, septum_turn_deg: null })) };
    expect(largestTurnDeg(none)).toBeNull();
    expect(studyLine(none)).toBe("3 files, 24x48, septum of phase ED (the RV contours' centre (120))");
    const details = studyDetails(r).split('\n');
    expect(details).toContain('LV_ENDO: mean displacement from phase ED up to 12.63 mm (phase ES), largest 25.27 mm');
    expect(details).toContain('LV_EPI: mean displacement from phase ED up to 10.37 mm (phase ES), largest 20.74 mm');
    expect(details.at(-1)).toBe('no LV_ENDO in phase MS: no closed mesh of this surface in this phase');
  });
});
