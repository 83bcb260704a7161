// The Contours panel's CSV (web/src/io/export/contourCsv.ts): every export's `#` header, the
// columns, one line per row in the order given (the panel's sort), ids quoted as the Distances CSV
// quotes them, distances to 4 decimals and empty without a figure, the file named as the run's
// other exports (with its frame).
import { describe, expect, it } from 'vitest';
import { contourCsvFileName, writeContourCsv } from '../../web/src/io/export/contourCsv';
import { csvField } from '../../web/src/io/export/csvField';
import type { ExportInfo } from '../../web/src/io/export/header';
import type { ContourRow } from '../../web/src/ui/contourRows';

const INFO: ExportInfo = {
  appVersion: '0.1.0', coreVersion: '0.2.0', fileName: 'biv me.h5', surface: 'LV_ENDO', frame: '3', lids: 'auto', params: { iterations: 250, beta: 0.1 }, leaveOut: ['s7,LAX'],
};

/** A row with what the CSV reads (the panel's words are not in it). */
const row = (id: string, state: ContourRow['state'], kind: ContourRow['kind'], count: number, line: number | null, mean: number | null, median: number | null, max: number | null): ContourRow => ({
  id, kind, state, count, line, meanMm: mean, medianMm: median, maxMm: max, reason: null, note: null, spikes: 0, far: 0, offPlane: 0, detail: null,
});

describe('the Contours CSV', () => {
  it('writes the header, the columns and one line per row in the order given', () => {
    // Not the file's order (a sort by max): the file keeps it.
    const rows = [
      row('s7,LAX', 'by_user', 'LAX', 40, 700, 1.23456, 1.143, 7.66489),
      { ...row('s2 "apex"', 'used', 'SAX', 52, null, 0.1, 0.05, 12.3), spikes: 2 },
      { ...row('lax1', 'used', 'LAX', 60, null, 0.2, 0.1, 1.5), far: 1 },
      { ...row('s03_RV', 'used', 'SAX', 38, null, 0.3, 0.2, 2.5), offPlane: 3 },
      row('s10', 'used', 'SAX', 48, null, 0, 0, 0.00004),
      row('sax11', 'speck', null, 0, 1505, null, null, null),
      row('s9', 'stray', 'SAX', 12, null, 180.5, 180.25, 181),
      row('lax2', 'lax_speck', 'LAX', 5, 2201, 3, null, 4),
    ];
    expect(writeContourCsv(rows, INFO)).toBe(
      [
        '# heartmesh 0.1.0 (core 0.2.0), units: mm',
        '# input: biv me.h5 surface: LV_ENDO frame: 3',
        '# lids: auto iterations=250 beta=0.1 leave_out=s7,LAX',
        'contour,kind,state,line,points,mean_mm,median_mm,max_mm,spike_points,far_points,off_plane_points',
        '"s7,LAX",LAX,by_user,700,40,1.2346,1.1430,7.6649,0,0,0',
        '"s2 ""apex""",SAX,used,,52,0.1000,0.0500,12.3000,2,0,0',
        'lax1,LAX,used,,60,0.2000,0.1000,1.5000,0,1,0',
        's03_RV,SAX,used,,38,0.3000,0.2000,2.5000,0,0,3',
        's10,SAX,used,,48,0.0000,0.0000,0.0000,0,0,0',
        'sax11,,speck,1505,0,,,,0,0,0',
        's9,SAX,stray,,12,180.5000,180.2500,181.0000,0,0,0',
        'lax2,LAX,lax_speck,2201,5,3.0000,,4.0000,0,0,0',
        '',
      ].join('\n'),
    );
    // A figure not finite is none, as in the Distances CSV.
    expect(writeContourCsv([row('s1', 'used', 'SAX', 1, null, Number.NaN, Number.POSITIVE_INFINITY, 1)], INFO).split('\n')[4]).toBe('s1,SAX,used,,1,,,1.0000,0,0,0');
    // No rows: the header and the columns only.
    expect(writeContourCsv([], INFO).split('\n').slice(3)).toEqual(['contour,kind,state,line,points,mean_mm,median_mm,max_mm,spike_points,far_points,off_plane_points', '']);
  });

  it('quotes as the Distances CSV does', () => {
    expect([csvField('s1'), csvField('a,b'), csvField('say "x"'), csvField('two\nlines')]).toEqual(['s1', '"a,b"', '"say ""x"""', '"two\nlines"']);
  });

  it('is named as the run\'s other exports, with the frame when the file has several', () => {
    expect(contourCsvFileName(INFO)).toBe('biv_me-LV_ENDO-frame3-contours.csv');
    expect(contourCsvFileName({ ...INFO, fileName: 'patient1-ED.csv', frame: null })).toBe('patient1-ED-LV_ENDO-contours.csv');
  });
});
