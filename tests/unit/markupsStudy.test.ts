// Slicer markups opened together (io/markupsStudy.ts): a folder of `.mrk.json` files, one curve
// each, joined into one markups file in name order; other files and broken markups left as given.
import { describe, expect, it } from 'vitest';
import lvEndo2 from '../../wasm-core/crates/heartmesh-core/tests/data/slicer-markups-patient1/s02_SAX_LV_ENDOCARDIAL.mrk.json?raw';
import { fcsvMarkup, isFcsvText, isMarkupsHead, isPointsTableText, joinedName, joinedText, joinMarkups, markupsStem, tableMarkup } from '../../web/src/io/markupsStudy';
import { holdsCurves, namesWall } from '../../web/src/io/slicerScene';

const bytes = (s: string) => new TextEncoder().encode(s);
const file = (name: string, text: string, lastModified = 1000) => new File([text], name, { lastModified });
const schema = 'https://raw.githubusercontent.com/slicer/slicer/master/Modules/Loadable/Markups/Resources/Schema/markups-schema-v1.0.3.json#';
const curve = (name: string | null, z: number) =>
  JSON.stringify({
    '@schema': schema,
    markups: [{ type: 'ClosedCurve', ...(name ? { name } : {}), controlPoints: [0, 1, 2].map((k) => ({ position: [Math.cos(k), Math.sin(k), z] })) }],
  });

describe('Slicer markups files', () => {
  it('tells a markups file by its content, as the core does', () => {
    expect(isMarkupsHead(bytes(lvEndo2))).toBe(true);
    expect(isMarkupsHead(bytes('\uFEFF  {"markups": [{"type": "Curve", "controlPoints": []}]}'))).toBe(true);
    expect(isMarkupsHead(bytes('{"heartmesh_session": 1, "contours": []}'))).toBe(false);
    expect(isMarkupsHead(bytes('[{"markups-schema": 1}]'))).toBe(false);
    expect(markupsStem('LV_ENDO_3.mrk.json')).toBe('LV_ENDO_3');
    expect(markupsStem('C.JSON')).toBe('C');
    expect(markupsStem('notes.txt')).toBe('notes.txt');
  });

  it('joins two or more in name order, naming the unnamed by their files, and leaves the rest', async () => {
    const given = [
      file('s10.mrk.json', curve('LV_ENDO_10', 10), 3000),
      file('GPFile_000.txt', 'not markups'),
      file('s09.mrk.json', curve(null, 9), 2000),
      file('broken.mrk.json', `{"@schema": "${schema}", "markups": [`),
    ];
    const { files, joined, names } = await joinMarkups(given);
    expect(joined).toBe(2);
    expect(names).toEqual([joinedName(2)]);
    expect(files.map((f) => f.name)).toEqual(['Slicer markups (2 files).mrk.json', 'GPFile_000.txt', 'broken.mrk.json']);
    const doc = JSON.parse(await files[0].text());
    expect(doc['@schema']).toBe(schema);
    // Code-unit order, as the core orders a folder's files: s09 before s10.
    expect(doc.markups.map((m: { name: string }) => m.name)).toEqual(['s09', 'LV_ENDO_10']);
    expect(doc.markups[1].controlPoints[2].position[2]).toBe(10);
    // Dropped again, the same file to the app (its size and date).
    expect(files[0].lastModified).toBe(3000);
    const again = await joinMarkups(given);
    expect(again.files[0].size).toBe(files[0].size);
    expect(joinedText(2, names)).toBe('2 Slicer markups files were read as one contour set: Slicer markups (2 files).mrk.json.');
  });

  it('joins nothing when fewer than two files are markups', async () => {
    const one = [file('a.mrk.json', curve('A', 0)), file('b.csv', 'contour,x,y,z')];
    const out = await joinMarkups(one);
    expect(out.joined).toBe(0);
    expect(out.files).toEqual(one);
    const session = [file('a.json', '{"heartmesh_session": 1}'), file('b.json', '{"heartmesh_session": 1}')];
    expect((await joinMarkups(session)).joined).toBe(0);
  });

  it('names the markups of a file holding several by file and number', async () => {
    const two = JSON.stringify({ '@schema': schema, markups: [JSON.parse(curve(null, 0)).markups[0], JSON.parse(curve(null, 5)).markups[0]] });
    const { files } = await joinMarkups([file('rings.mrk.json', two), file('z.mrk.json', curve('Z', 9))]);
    const doc = JSON.parse(await files[0].text());
    expect(doc.markups.map((m: { name: string }) => m.name)).toEqual(['rings-1', 'rings-2', 'Z']);
  });

  it('joins folders whose curves share names apart (a phase or a patient each), and others together', async () => {
    const inFolder = new Map<File, string>();
    const at = (folder: string, f: File) => (inFolder.set(f, folder), f);
    const folderOf = (f: File) => inFolder.get(f) ?? '';
    const phases = [
      at('p1/ED', file('LV_ENDO_1.mrk.json', curve(null, 0), 1000)),
      at('p1/ES', file('LV_ENDO_1.mrk.json', curve(null, 0), 2000)),
      at('p1/ED', file('LV_ENDO_2.mrk.json', curve('LV_ENDO_2', 10), 1000)),
      at('p1/ES', file('LV_ENDO_2.mrk.json', curve('LV_ENDO_2', 10), 2000)),
      at('p1/ES', file('notes.txt', 'x')),
    ];
    const split = await joinMarkups(phases, folderOf);
    expect(split.joined).toBe(4);
    expect(split.names).toEqual(['ED (2 Slicer markups).mrk.json', 'ES (2 Slicer markups).mrk.json']);
    expect(split.files.map((f) => f.name)).toEqual([...split.names, 'notes.txt']);
    for (const f of split.files.slice(0, 2)) {
      expect(JSON.parse(await f.text()).markups.map((m: { name: string }) => m.name)).toEqual(['LV_ENDO_1', 'LV_ENDO_2']);
    }
    expect(split.files[1].lastModified).toBe(2000);
    expect(joinedText(4, split.names)).toBe(
      '4 Slicer markups files were read as 2 contour sets, one per folder (the folders\' curves share names: a phase or a patient each): ED (2 Slicer markups).mrk.json, ES (2 Slicer markups).mrk.json.',
    );
    // The LV's curves beside the RV's: one set.
    const sides = [at('p1/LV', file('LV_ENDO_1.mrk.json', curve(null, 0))), at('p1/RV', file('RV_ENDO_1.mrk.json', curve(null, 0)))];
    expect((await joinMarkups(sides, folderOf)).names).toEqual(['Slicer markups (2 files).mrk.json']);
  });

  describe('legacy point list files (.fcsv)', () => {
    const header = '# Markups fiducial file version = 5.6\n# CoordinateSystem = LPS\n# columns = id,x,y,z,ow,ox,oy,oz,vis,sel,lock,label,desc,associatedNodeID\n';
    const ring = (z: number, label = 'F') =>
      header + [0, 1, 2, 3, 4, 5].map((k) => `${k + 1},${10 * Math.cos(k)},${10 * Math.sin(k)},${z},0,0,0,1,1,1,0,${label}-${k + 1},"a, note",,2,0`).join('\n') + '\n';

    it('tells one by its header and reads it as the point list Slicer makes of it', () => {
      expect(isFcsvText(ring(0))).toBe(true);
      expect(isMarkupsHead(bytes(ring(0)))).toBe(true);
      expect(isFcsvText('# columns = id,label,z,y,x\n1,A,3,2,1\n')).toBe(true);
      expect(isFcsvText('contour,x,y,z\nc1,1,2,3\n')).toBe(false);
      expect(isFcsvText('1 2 3\n4 5 6\n')).toBe(false);
      expect(markupsStem('LV_ENDO_3.fcsv')).toBe('LV_ENDO_3');
      const m = fcsvMarkup('LV_ENDO_3', ring(7)) as { type: string; coordinateSystem: string; controlPoints: { label: string; position: number[] }[] };
      expect(m.type).toBe('Fiducial');
      expect(m.coordinateSystem).toBe('LPS');
      expect(m.controlPoints).toHaveLength(6);
      // The quoted description's comma shifts nothing.
      expect(m.controlPoints[1]).toEqual({ label: 'F-2', position: [10 * Math.cos(1), 10 * Math.sin(1), 7] });
      // Slicer before 4.11: the frame by number (0 RAS, 1 LPS), or none (RAS); columns by name.
      const old = fcsvMarkup('F', '# CoordinateSystem = 1\nvtkMRMLMarkupsFiducialNode_0,1,2,3,0,0,0,1,1,1,0,,,\n') as { coordinateSystem: string; controlPoints: { label: string }[] };
      expect(old.coordinateSystem).toBe('LPS');
      expect(old.controlPoints[0].label).toBe('F-1');
      expect((fcsvMarkup('F', '# Markups fiducial file version = 4.4\n1,4,5,6\n') as { coordinateSystem: string }).coordinateSystem).toBe('RAS');
      const moved = fcsvMarkup('F', '# columns = id,label,z,y,x\n1,A,3,2,1\n') as { controlPoints: { position: number[] }[] };
      expect(moved.controlPoints[0].position).toEqual([1, 2, 3]);
      // A row the core would refuse: not converted (opened alone, the core names the line).
      expect(fcsvMarkup('F', header + '1,1,zero,3\n')).toBeNull();
      expect(fcsvMarkup('F', '# CoordinateSystem = IJK\n1,1,2,3\n')).toBeNull();
    });

    it('joins a folder of them (and .mrk.json beside them) into one markups file; a damaged one opens alone', async () => {
      const given = [
        file('LV_ENDO_2.fcsv', ring(10), 2000),
        file('LV_ENDO_1.fcsv', ring(0), 1000),
        file('LV_ENDO_3.mrk.json', curve('LV_ENDO_3', 20), 500),
        file('LV_ENDO_4.fcsv', header + '1,1,2\n'),
      ];
      const { files, joined } = await joinMarkups(given);
      expect(joined).toBe(3);
      expect(files.map((f) => f.name)).toEqual(['Slicer markups (3 files).mrk.json', 'LV_ENDO_4.fcsv']);
      const doc = JSON.parse(await files[0].text());
      expect(doc.markups.map((m: { name: string; type: string }) => `${m.name} ${m.type}`)).toEqual(['LV_ENDO_1 Fiducial', 'LV_ENDO_2 Fiducial', 'LV_ENDO_3 ClosedCurve']);
      expect(doc.markups[1].controlPoints[0].position[2]).toBe(10);
      expect(files[0].lastModified).toBe(2000);
    });

    it('counts as a scene\'s curves when drawn along a contour, not when it holds landmarks', () => {
      expect(holdsCurves(ring(0), 'F')).toBe(true);
      expect(holdsCurves(ring(0, 'RV_INSERT'), 'F')).toBe(false);
      expect(holdsCurves(ring(0), 'Apex points')).toBe(false);
      expect(holdsCurves(header + '1,1,2,3,0,0,0,1,1,1,0,F-1,,\n', 'F')).toBe(false);
      // Points over several images: landmarks, as the core reads them.
      const spread = header + [0, 1, 2, 3, 4].map((k) => `${k + 1},${10 * Math.cos(k)},${10 * Math.sin(k)},${12 * k},0,0,0,1,1,1,0,F-${k + 1},,`).join('\n');
      expect(holdsCurves(spread, 'F')).toBe(false);
      // A markups JSON point list clicked round a ring counts too; one of named landmarks does not.
      const list = (label: string) => JSON.stringify({ markups: [{ type: 'Fiducial', name: 'F', controlPoints: [0, 1, 2, 3, 4, 5].map((k) => ({ label: `${label}-${k}`, position: [10 * Math.cos(k), 10 * Math.sin(k), 3] })) }] });
      expect(holdsCurves(list('F'), 'F')).toBe(true);
      expect(holdsCurves(list('APEX'), 'F')).toBe(false);
    });

    it('counts a list named after a wall as a contour whatever its size, as the core does', () => {
      const three = header + [0, 1, 2].map((k) => `${k + 1},${10 * Math.cos(k)},${10 * Math.sin(k)},${12 * k},0,0,0,1,1,1,0,,,`).join('\n');
      // Three points, 24 mm apart in z: landmarks unless the name says which wall they trace.
      expect(holdsCurves(three, 'F')).toBe(false);
      for (const wall of ['LV_ENDO_s3', 'lvendo 4', 'RV free wall', 'rv-septum', 'Left epicardium'])
        expect([wall, holdsCurves(three, wall)]).toEqual([wall, true]);
      // An LV with an RV part, a side with no wall, a wall with no side, a landmark word: not.
      for (const other of ['LV septum', 'LV 3', 'endocardium', 'LV endo apex'])
        expect([other, holdsCurves(three, other)]).toEqual([other, false]);
      expect(namesWall('RVfreewall')).toBe(true);
      expect(namesWall('lvepi')).toBe(true);
      expect(namesWall('lvx')).toBe(false);
      expect(holdsCurves(header, 'LV_ENDO')).toBe(false);
    });

    it('reads a control points table (Slicer\'s export to CSV) the same way, in the frame its columns say', async () => {
      const table = 'label,l,p,s,defined,selected,visible,locked,description\nA-1,1.5,2,3,1,1,1,0,"a, note"\nA-2,4,5,6,0,1,1,0,\n,7,8,9,true,1,1,0,\n';
      expect(isPointsTableText(table)).toBe(true);
      expect(isMarkupsHead(bytes(table))).toBe(true);
      expect(isPointsTableText('contour,x,y,z\nc,1,2,3\n')).toBe(false);
      expect(isPointsTableText('label,x,y,z\nc,1,2,3\n')).toBe(false);
      expect(markupsStem('LV_ENDO_3.csv')).toBe('LV_ENDO_3');
      const m = tableMarkup('LV_ENDO_3', table) as { coordinateSystem: string; controlPoints: { label: string; position: number[] }[] };
      expect(m.coordinateSystem).toBe('LPS');
      // The point not placed (defined 0) is left out; the unlabelled one is numbered.
      expect(m.controlPoints).toEqual([
        { label: 'A-1', position: [1.5, 2, 3] },
        { label: 'LV_ENDO_3-2', position: [7, 8, 9] },
      ]);
      expect((tableMarkup('B', 'label,r,a,s\nB,1,2,3\n') as { coordinateSystem: string }).coordinateSystem).toBe('RAS');
      expect(tableMarkup('B', 'label,r,a,s\nB,1,x,3\n')).toBeNull();
      const { files, joined } = await joinMarkups([file('LV_ENDO_1.csv', table), file('LV_ENDO_2.fcsv', '# Markups fiducial file version = 4.10\n1,1,2,3\n'), file('other.csv', 'contour,x,y,z\n')]);
      expect(joined).toBe(2);
      expect(files.map((f) => f.name)).toEqual(['Slicer markups (2 files).mrk.json', 'other.csv']);
    });
  });
});
