// The core's Slicer markups fixture (biv-me patient 1's ED curves, one `.mrk.json` per curve) as
// Slicer 4 left such a study: one legacy point list file (`.fcsv`) per markup, the points of its
// first stretch (a point list holds one), Slicer 5's two extra fields on every row. `ras`: every
// other file in RAS (x and y negated), as a study gathered from several sessions may be.
import { readdirSync, readFileSync } from 'node:fs';
import { join } from 'node:path';
import { ROOT } from './lib.mjs';

export const MARKUPS_FIXTURE = join(ROOT, 'wasm-core', 'crates', 'heartmesh-core', 'tests', 'data', 'slicer-markups-patient1');

/** `heartmesh reconstruct` of these files, LV_ENDO (ml), in either frame mix. */
export const FCSV_LV_ENDO_ML = 171.61;

/** File name -> text of each point list file. */
export function fcsvFiles({ ras = false } = {}) {
  const files = {};
  for (const [k, name] of readdirSync(MARKUPS_FIXTURE).sort().entries()) {
    const m = JSON.parse(readFileSync(join(MARKUPS_FIXTURE, name), 'utf8')).markups[0];
    const flip = ras && k % 2 === 1;
    const rows = m.controlPoints
      .filter((p) => (p.positionStatus ?? 'defined') === 'defined')
      .map((p, i) => {
        const [x, y, z] = p.position;
        return `${i + 1},${flip ? -x : x},${flip ? -y : y},${z},0,0,0,1,1,1,0,${p.label},,vtkMRMLScalarVolumeNode1,2,0`;
      });
    const header = `# Markups fiducial file version = 5.6\n# CoordinateSystem = ${flip ? 'RAS' : 'LPS'}\n# columns = id,x,y,z,ow,ox,oy,oz,vis,sel,lock,label,desc,associatedNodeID\n`;
    files[name.replace(/\.mrk\.json$/, '.fcsv')] = header + rows.join('\n') + '\n';
  }
  return files;
}
