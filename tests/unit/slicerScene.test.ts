// A 3D Slicer scene opened whole (io/slicerScene.ts): its folder or .mrb bundle's files, the
// scene file told by its root element; the curves opened and the rest set aside, else the
// segmentations opened and the scene file and point lists set aside.
import { describe, expect, it } from 'vitest';
import lvEndo2 from '../../wasm-core/crates/heartmesh-core/tests/data/slicer-markups-patient1/s02_SAX_LV_ENDOCARDIAL.mrk.json?raw';
import insertions from '../../wasm-core/crates/heartmesh-core/tests/data/slicer-markups-patient1/RV insertions.mrk.json?raw';
import { holdsCurves, isMrmlHead, sceneAsideText, sceneOf } from '../../web/src/io/slicerScene';

const bytes = (s: string): Uint8Array<ArrayBuffer> => new TextEncoder().encode(s);
const file = (name: string, body: string | Uint8Array<ArrayBuffer>) => new File([body], name);
const SCENE = '<?xml version="1.0" encoding="UTF-8"?>\n<MRML  version="Slicer4.4.0" userTags="">\n</MRML>\n';
const names = (files: { name: string }[]) => files.map((f) => f.name);

describe('3D Slicer scenes', () => {
  it('tells a scene file by its root element, as the core does', () => {
    expect(isMrmlHead(bytes(SCENE))).toBe(true);
    expect(isMrmlHead(bytes('\uFEFF <!-- saved -->\n<mrml>'))).toBe(true);
    expect(isMrmlHead(bytes('<MRMLX>'))).toBe(false);
    expect(isMrmlHead(bytes('<?xml version="1.0"?>\n<VTKFile type="PolyData">'))).toBe(false);
    expect(isMrmlHead(bytes('<!-- never closed <MRML>'))).toBe(false);
    expect(holdsCurves(lvEndo2)).toBe(true);
    expect(holdsCurves(insertions)).toBe(false);
  });

  it('opens the curves of a scene and sets the rest aside, named', async () => {
    const given = [
      file('Scene.mrml', SCENE),
      file('cine.nrrd', bytes('NRRD0004\ntype: short\n')),
      file('s02_SAX_LV_ENDOCARDIAL.mrk.json', lvEndo2),
      file('RV insertions.mrk.json', insertions),
      file('Segmentation.seg.nrrd', bytes('NRRD0004\ntype: uchar\n')),
    ];
    const scene = await sceneOf(given);
    expect(scene).not.toBeNull();
    expect(names(scene!.files)).toEqual(['s02_SAX_LV_ENDOCARDIAL.mrk.json', 'RV insertions.mrk.json']);
    expect(scene!.aside).toEqual(['Scene.mrml', 'cine.nrrd', 'Segmentation.seg.nrrd']);
    expect(sceneAsideText(scene!.aside, scene!.source)).toBe(
      '3 other files of the Slicer scene set aside (the contours come from the Slicer markups): Scene.mrml, cine.nrrd, Segmentation.seg.nrrd (a segmentation: open it alone to read it instead).',
    );
    expect(sceneAsideText(['Scene.mrml'], 'its segmentations')).toBe('1 other file of the Slicer scene set aside (the contours come from its segmentations): Scene.mrml.');
  });

  it('without curves opens the segmentations (and scans, which the core sets aside) and sets the scene file and points aside', async () => {
    const given = [file('RV insertions.mrk.json', insertions), file('Scene.mrml', SCENE), file('Segmentation.seg.nrrd', 'NRRD0004\n'), file('cine.nrrd', 'NRRD0004\n')];
    const scene = await sceneOf(given);
    expect(names(scene!.files)).toEqual(['Segmentation.seg.nrrd', 'cine.nrrd']);
    expect(scene!.aside).toEqual(['RV insertions.mrk.json', 'Scene.mrml']);
    expect(scene!.source).toBe('its segmentations');
    // A scene file alone is opened, so the core says what to open instead; points alone too.
    expect(names((await sceneOf([file('Scene.mrml', SCENE)]))!.files)).toEqual(['Scene.mrml']);
    expect(names((await sceneOf([file('Scene.mrml', SCENE), file('F.mrk.json', insertions)]))!.files)).toEqual(['F.mrk.json']);
  });

  it('leaves files without a scene file as given, and keeps a damaged markups file with the curves', async () => {
    expect(await sceneOf([file('a.mrk.json', lvEndo2), file('cine.nrrd', 'NRRD0004\n')])).toBeNull();
    const broken = '{"@schema": "markups-schema", "markups": [';
    const scene = await sceneOf([file('Scene.mrml', SCENE), file('b.mrk.json', broken), file('cine.nrrd', 'x')]);
    expect(names(scene!.files)).toEqual(['b.mrk.json']);
    expect(scene!.source).toBe('the Slicer markups');
  });
});
