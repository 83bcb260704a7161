import { describe, expect, it } from 'vitest';
import { bannerText, taubinHint, wrongFileHint } from '../../web/src/ui/ErrorBanner';

describe('error banner hints', () => {
  it('explains the Taubin limit of the smoothing factor, and nothing else', () => {
    const taubin = { code: 'param_out_of_range', message: 'parameter smoothing_factor = 0.8 is out of range (allowed 0 to 0.6)' };
    expect(taubinHint(taubin)).toBe(' — with Taubin (λ/μ) smoothing the factor must be at most 0.6: lower it, or choose Laplacian + affine correction.');
    // Twicing's limit is 0.5: the hint names the method chosen, not both.
    expect(taubinHint({ code: 'param_out_of_range', message: 'parameter smoothing_factor = 0.55 is out of range (allowed 0 to 0.5)' }))
      .toBe(' — with twicing smoothing the factor must be at most 0.5: lower it, or choose Laplacian + affine correction.');
    // The slider's own range (0 to 1) is not the Taubin limit; other parameters and codes get no hint.
    expect(taubinHint({ code: 'param_out_of_range', message: 'parameter smoothing_factor = 2 is out of range (allowed 0 to 1)' })).toBe('');
    expect(taubinHint({ code: 'param_out_of_range', message: 'parameter beta = 2 is out of range (allowed 0.01 to 1)' })).toBe('');
    expect(taubinHint({ code: 'param_invalid', message: taubin.message })).toBe('');
  });
});

describe('a picture opened by mistake', () => {
  it('says it is a picture and what to open instead', () => {
    const hint = wrongFileHint({ code: 'parse', message: 'image.png, line 1: binary data at byte 0: not a UTF-8 text file' });
    expect(hint).toBe(' This is a picture (PNG), not contours: open the contours drawn on the images (CSV, biv-me GPFile, a Segment or SurFCo .mat, DICOM RT structure set) or their segmentation (a NIfTI label map).');
    expect(wrongFileHint({ code: 'parse', message: 'slice 3.JPG, line 1: binary data at byte 0: not a UTF-8 text file' })).toContain('a picture (JPEG)');
    expect(wrongFileHint({ code: 'parse', message: 'scan.tif, line 1: binary data at byte 2: not a UTF-8 text file' })).toContain('a picture (TIFF)');
    // The worker's errors name the file apart from the message.
    expect(wrongFileHint({ code: 'parse', file: 'shot.png', line: 1, message: 'binary data at byte 0: not a UTF-8 text file' })).toContain('a picture (PNG)');
    // The core names the pictures it knows by their signature: only what to open is added.
    expect(wrongFileHint({ code: 'parse', message: 'shot.dat, line 1: binary data at byte 0: this is a JPEG picture, not contours' })).toBe(
      ' Instead, open the contours drawn on the images (CSV, biv-me GPFile, a Segment or SurFCo .mat, DICOM RT structure set) or their segmentation (a NIfTI label map).');
    // Other binary files, and a PNG refused for another reason, get no such hint.
    expect(wrongFileHint({ code: 'parse', message: 'junk.bin, line 1: binary data at byte 1: not a UTF-8 text file' })).toBe('');
    expect(wrongFileHint({ code: 'parse', message: 'a.png: empty file' })).toBe('');
  });
});

describe('error banner text', () => {
  it('ends the message with a full stop before a following sentence, once', () => {
    const msg = 'SliceInfoFile.txt, line 1: this is a biv-me SliceInfoFile (image planes), not contours; read the GPFile_*.txt beside it';
    expect(bannerText(msg, ' Not opened; still showing GPFile_000.txt.')).toBe(`${msg}. Not opened; still showing GPFile_000.txt.`);
    expect(bannerText('bad.csv: too few points.', ' Not opened.')).toBe('bad.csv: too few points. Not opened.');
    // A hint that continues the sentence, or nothing after: unchanged.
    expect(bannerText('parameter smoothing_factor = 0.8 is out of range', ' — with Taubin smoothing ...')).toBe('parameter smoothing_factor = 0.8 is out of range — with Taubin smoothing ...');
    expect(bannerText('a.csv: factorisation failed', '')).toBe('a.csv: factorisation failed');
  });
});

describe('error banner: files opened by mistake', () => {
  it('the Parameters JSON export and a mesh say what to open instead; other errors get nothing', () => {
    // The core's messages for them (seen in session 14 with the app's own exports dropped back).
    const params = { code: 'parse', line: 44, message: 'line 44: invalid session JSON: missing field `heartmesh_session`' };
    expect(wrongFileHint(params)).toBe(' Only a heartmesh session opens here (the Session export, …-session.json); the Parameters JSON export holds no contours.');
    expect(wrongFileHint({ code: 'parse', message: 'this is a mesh file (OBJ, STL or PLY), not contours' })).toMatch(/open it in the Lab tab as the truth/);
    expect(wrongFileHint({ code: 'parse', line: 3, message: 'line 3: column "y": "oops" is not a number' })).toBe('');
    // The hint follows the message as its own sentence.
    expect(bannerText('a-params.json, line 44: invalid session JSON: missing field `heartmesh_session`', wrongFileHint(params))).toMatch(/`heartmesh_session`\. Only a heartmesh session/);
  });
});
