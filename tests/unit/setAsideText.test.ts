// The banner's note on the SliceInfoFiles set aside in a drop: two biv-me patient folders dropped
// together gave "SliceInfoFile.txt, SliceInfoFile.txt set aside: ...".
import { describe, expect, it } from 'vitest';
import { imagesAsideText, isDicomImageRefusal, isImageRefusal, setAsideText } from '../../web/src/app/errors';

describe('setAsideText', () => {
  it('names one file, and counts files of one name instead of repeating it', () => {
    expect(setAsideText(['SliceInfoFile.txt'], 'GPFile_000.txt')).toBe(
      'SliceInfoFile.txt set aside: image planes, not contours (the contours come from GPFile_000.txt; a SliceInfoFile is read with the GPFile of its folder, to check that each contour lies in its own plane).',
    );
    expect(setAsideText(['SliceInfoFile.txt', 'SliceInfoFile.txt'], 'GPFile_000.txt')).toMatch(/^2 files named SliceInfoFile\.txt set aside: image planes/);
    expect(setAsideText(['SliceInfoFile.txt', 'SliceInfo_ES.txt', 'SliceInfoFile.txt'], 'a.txt')).toMatch(/^2 files named SliceInfoFile\.txt, SliceInfo_ES\.txt set aside/);
  });

  it('counts DICOM images opened with a segmentation as set aside, told by the core\'s message', () => {
    const image = { code: 'parse', file: 'IM_0001.dcm', message: 'this is a DICOM image (modality MR), not contours: open the contours drawn on it (an RT structure set, or a cvi42 workspace together with its images)' } as const;
    expect(isImageRefusal(image)).toBe(true);
    expect(isImageRefusal({ ...image, message: 'this DICOM file is not an RT structure set (modality SR, SOP class 1.2)' })).toBe(false);
    expect(isImageRefusal({ ...image, code: 'app' })).toBe(false);
    expect(imagesAsideText(1, 'seg.dcm')).toBe('1 DICOM image set aside: images, not contours (the contours come from seg.dcm).');
    expect(imagesAsideText(240, 'seg.dcm')).toMatch(/^240 DICOM images set aside/);
  });

  it('counts scans of a label-map format (a Slicer scene\'s) as images set aside, told by the core\'s message', () => {
    const scan = { code: 'parse', file: 'cine.nrrd', message: 'this NRRD is an image, not a label map (segmentation): it holds more than 64 values; open the segmentation (background 0, one whole number per structure)' } as const;
    expect(isImageRefusal(scan)).toBe(true);
    expect(isDicomImageRefusal(scan)).toBe(false);
    expect(isImageRefusal({ ...scan, message: scan.message.replace('NRRD', 'NIfTI') })).toBe(true);
    expect(isImageRefusal({ ...scan, message: 'the NRRD sizes 1 x 2 are too large' })).toBe(false);
    expect(imagesAsideText(1, 'seg.seg.nrrd', 'image')).toBe('1 image set aside: images, not contours (the contours come from seg.seg.nrrd).');
    expect(imagesAsideText(2, 'seg.seg.nrrd', 'image')).toMatch(/^2 images set aside/);
  });
});
