// Files as other tools write them (session 16) through the worker's logic with the real wasm: a
// UTF-16 file (Excel's "Unicode text"), a Windows-1252 one, a classic-Mac CR one and one with
// units and a slice column load with the canonical file's points; decimal commas with comma
// separators and a two-frame file are told (an error naming line 2; a warning naming the frames),
// and after the error the same worker still loads and reconstructs a good file.
import { beforeAll, describe, expect, it } from 'vitest';
import type { LoadedFile } from '../../web/src/core-client/protocol';
import { SURFCO, loadWasm, readBytes } from './helpers.mjs';
import { askingCore } from './askCore';

type Wasm = typeof import('../../web/pkg/heartmesh_wasm.js');
let wasm: Wasm;
let text = '';

beforeAll(async () => {
  wasm = await loadWasm();
  text = new TextDecoder().decode(readBytes(SURFCO()));
});

function utf16le(s: string): Uint8Array {
  const out = new Uint8Array(2 + 2 * s.length);
  out.set([0xff, 0xfe]);
  for (let i = 0; i < s.length; i++) {
    const c = s.charCodeAt(i);
    out[2 + 2 * i] = c & 0xff;
    out[3 + 2 * i] = c >> 8;
  }
  return out;
}

/** Latin-1 / Windows-1252 bytes of a string whose characters are all below 256. */
function singleByte(s: string): Uint8Array {
  return Uint8Array.from(s, (c) => c.charCodeAt(0));
}

function dataRows(f: (row: string) => string): string {
  const rows = text.split(/\r?\n/).slice(1).filter((l) => l.length > 0);
  return rows.map(f).join('\n') + '\n';
}

describe('files from other tools, through the worker', () => {
  it('reads other encodings and layouts like the canonical file, and tells what it cannot read', async () => {
    const { ask } = askingCore(wasm);
    let reqId = 0;
    const load = (fileName: string, bytes: Uint8Array) =>
      ask({ type: 'load', reqId: ++reqId, fileName, bytes: bytes.slice().buffer as ArrayBuffer }, 'loaded', 'error');
    const canonical = await load('canonical.csv', new TextEncoder().encode(text));
    expect(canonical.type).toBe('loaded');
    const want = Array.from((canonical as { file: LoadedFile }).file.points);
    expect(want.length).toBe(3 * 3008);

    const variants: [string, Uint8Array][] = [
      ['excel-unicode.txt', utf16le(text.replaceAll(',', '\t').replaceAll('\n', '\r\n'))],
      ['ansi.csv', singleByte('contour,x,y,z\n' + dataRows((l) => `r\u00e9gion ${l}`))],
      ['mac.csv', new TextEncoder().encode(text.replaceAll('\n', '\r'))],
      ['units.csv', new TextEncoder().encode(text.replace('contour,x,y,z', 'slice,X (mm),Y [mm],z_mm'))],
    ];
    for (const [name, bytes] of variants) {
      const got = await load(name, bytes);
      expect(got.type, name).toBe('loaded');
      const file = (got as { file: LoadedFile }).file;
      expect(Array.from(file.points), name).toEqual(want);
      expect(file.contours.length, name).toBe(8);
    }

    const comma = await load('comma.csv', new TextEncoder().encode('contour,x,y,z\n' + dataRows((l) => l.replaceAll('.', ','))));
    expect(comma.type).toBe('error');
    const error = (comma as { error: { code: string; message: string; line?: number | null } }).error;
    expect(error.code).toBe('parse');
    expect(error.message).toContain('row has 7 fields but the header names 4 columns; decimal commas');

    const two = 'contour,x,y,z,frame\n' + dataRows((l) => `${l},0`) + dataRows((l) => `${l},1`);
    const frames = await load('cine.csv', new TextEncoder().encode(two));
    expect(frames.type, JSON.stringify((frames as { error?: unknown }).error)).toBe('loaded');
    const cine = (frames as { file: LoadedFile }).file;
    expect(Array.from(cine.points)).toEqual(want);
    expect(cine.warnings[0]).toMatch(/^the file holds 2 time frames \(0, 1\): frame 0 read, 3014 points of other frames left out/);

    // The worker is alive: a run on the canonical file finishes.
    const done = await ask({ type: 'run', runId: 3, fileName: 'canonical.csv', surface: null, params: { iterations: 10 }, lids: 'auto' }, 'done', 'error');
    expect(done.type).toBe('done');
  });
});
