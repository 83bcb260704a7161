// UK Biobank's ZIP archives of a cvi42 study opened as the app opens them (io/zipArchive.ts, then
// io/cvi42Study.ts and io/dicomHeaders.ts), through the worker's logic and the real wasm, on the
// core's fixture (zipped/1000001_cvi42.zip, zipped/1000001_images.zip: the study beside them,
// packed). The members are the loose files (the images as their headers), the reading equals the
// loose study's, and the mesh is the command line's of the same two archives
// (`heartmesh reconstruct 1000001_cvi42.zip 1000001_images.zip --surface LV_ENDO`).
import { beforeAll, describe, expect, it } from 'vitest';
import { DEFAULT_OPTIONS, type LoadedFile, type RunResult, type ViewFile } from '../../web/src/core-client/protocol';
import { imageHeaders } from '../../web/src/io/dicomHeaders';
import { cvi42Study } from '../../web/src/io/cvi42Study';
import { pathInFolder } from '../../web/src/io/folderDrop';
import { expandArchives } from '../../web/src/io/zipArchive';
import { ROOT, cliReport, filesIn, loadWasm, readBytes } from './helpers.mjs';
import { askingCore, type Ask } from './askCore';

const DIR = `${ROOT}/wasm-core/crates/heartmesh-core/tests/data/cvi42-patient1`;
const WORKSPACE_ZIP = `${DIR}/zipped/1000001_cvi42.zip`;
const IMAGES_ZIP = `${DIR}/zipped/1000001_images.zip`;

type Wasm = typeof import('../../web/pkg/heartmesh_wasm.js');
let wasm: Wasm;
beforeAll(async () => {
  wasm = await loadWasm();
});

const buffer = (bytes: Uint8Array) => bytes.slice().buffer as ArrayBuffer;
const fileOf = (path: string) => new File([buffer(readBytes(path))], path.slice(path.lastIndexOf('/') + 1));

async function load(ask: Ask, name: string, bytes: ArrayBuffer, views: ViewFile[]): Promise<LoadedFile> {
  const m = await ask({ type: 'load', reqId: 1, fileName: name, bytes, views }, 'loaded', 'error');
  if (m.type === 'error') throw new Error(m.error.message);
  return m.file;
}

async function run(ask: Ask, name: string): Promise<RunResult> {
  const m = await ask({ type: 'run', runId: 1, fileName: name, surface: 'LV_ENDO', params: {}, lids: 'auto', options: { ...DEFAULT_OPTIONS } }, 'done', 'error');
  if (m.type === 'error') throw new Error(m.error.message);
  return m.result;
}

describe("UK Biobank's archives of a cvi42 study", () => {
  it('unpack into the workspace and its 110 images as headers, read as the loose study, meshed as the command line meshes the archives', async () => {
    const { files, refused, archives } = await expandArchives([fileOf(WORKSPACE_ZIP), fileOf(IMAGES_ZIP)]);
    expect(refused).toEqual([]);
    expect(archives).toBe(2);
    expect(files).toHaveLength(111);
    const study = cvi42Study(files);
    expect(study?.workspaces.map((f) => f.name)).toEqual(['1000001_cvi42.cvi42wsx']);
    const names = filesIn(`${DIR}/dicom`);
    expect(study?.images.map((f) => f.name)).toEqual(names);
    expect(study?.images.map(pathInFolder)).toEqual(names.map((n) => `1000001_images.zip/dicom/${n}`));
    // The workspace whole, each image its header: the loose file less its 20-byte pixel element.
    const workspace = new Uint8Array(await study!.workspaces[0].arrayBuffer());
    expect(workspace).toEqual(readBytes(`${DIR}/Contours.cvi42wsx`));
    for (const [i, f] of study!.images.entries()) {
      const loose = readBytes(`${DIR}/dicom/${names[i]}`);
      expect(new Uint8Array(await f.arrayBuffer())).toEqual(loose.subarray(0, loose.length - 20));
    }

    const { images, unreadable } = await imageHeaders(study!.images, pathInFolder);
    expect(unreadable).toEqual([]);
    const { ask } = askingCore(wasm);
    const zipped = await load(ask, '1000001_cvi42.cvi42wsx', buffer(workspace), images);
    const loose = await load(ask, 'Contours.cvi42wsx', buffer(readBytes(`${DIR}/Contours.cvi42wsx`)), names.map((n) => ({ name: n, bytes: buffer(readBytes(`${DIR}/dicom/${n}`)) })));
    expect(zipped.contours).toEqual(loose.contours);
    expect(zipped.warnings).toEqual(loose.warnings);
    expect(zipped.notes?.[0]).toMatch(/^workspace read with 110 DICOM images: contours on 17 of them, in 9 cine slices/);
    expect(zipped.timeFrames?.frames).toEqual(['0', '9']);

    await load(ask, '1000001_cvi42.cvi42wsx', buffer(workspace), images);
    const r = await run(ask, '1000001_cvi42.cvi42wsx');
    const report = cliReport(WORKSPACE_ZIP, [IMAGES_ZIP, '--surface', 'LV_ENDO'], 'cvi42-zipped-lv-endo');
    expect(r.positions.length / 3).toBe(1041);
    expect(r.positions.length / 3).toBe(report.vertices);
    expect(r.indices.length / 3).toBe(report.triangles);
    expect(r.overall.mean).toBeCloseTo(report.contour_to_mesh.mean, 6);
    expect(r.overall.mean.toFixed(3)).toBe('0.380');
    expect(r.volumeMl).toBeCloseTo(report.volume_ml, 6);
    expect(r.volumeMl.toFixed(1)).toBe('173.2');
  });
});
