/**
 * A reader of binary little-endian PLY, the form the core writes (`io/ply.rs`): scalar properties
 * of any PLY type and list properties (a count, then the items), per element, in file order. The
 * app reads the wall the worker built as PLY to show it (the PLY carries the per-vertex
 * `thickness` and the per-face `region`, which three.js's PLYLoader drops), so the solid on screen
 * is the file the user saves, not a second rendition of it. ASCII and big-endian PLY are refused:
 * the core never writes them, and this is no general importer.
 */

/** One element of the file (`vertex`, `face`, ...): its scalar properties and its list properties by name. */
export interface PlyElement {
  name: string;
  count: number;
  /** Each scalar property's values, one per item. */
  scalars: Map<string, Float64Array>;
  /** Each list property: every item's entries one after another, and where each item's start (`count + 1` offsets). */
  lists: Map<string, { values: Float64Array; offsets: Uint32Array }>;
}

export interface Ply {
  /** The `comment` lines of the header, without the keyword. */
  comments: string[];
  elements: Map<string, PlyElement>;
}

type Scalar = 'int8' | 'uint8' | 'int16' | 'uint16' | 'int32' | 'uint32' | 'float32' | 'float64';

/** The PLY type names (both spellings) and their layout. */
const TYPES: Record<string, Scalar> = {
  char: 'int8', int8: 'int8', uchar: 'uint8', uint8: 'uint8',
  short: 'int16', int16: 'int16', ushort: 'uint16', uint16: 'uint16',
  int: 'int32', int32: 'int32', uint: 'uint32', uint32: 'uint32',
  float: 'float32', float32: 'float32', double: 'float64', float64: 'float64',
};
const SIZE: Record<Scalar, number> = { int8: 1, uint8: 1, int16: 2, uint16: 2, int32: 4, uint32: 4, float32: 4, float64: 8 };

interface PropertyDecl {
  name: string;
  type: Scalar;
  /** The count's type, for a list property. */
  countType?: Scalar;
}

function scalarType(name: string | undefined, line: string): Scalar {
  const t = name === undefined ? undefined : TYPES[name];
  if (!t) throw new Error(`PLY: unknown property type in "${line}"`);
  return t;
}

function read(view: DataView, at: number, type: Scalar): number {
  switch (type) {
    case 'int8':
      return view.getInt8(at);
    case 'uint8':
      return view.getUint8(at);
    case 'int16':
      return view.getInt16(at, true);
    case 'uint16':
      return view.getUint16(at, true);
    case 'int32':
      return view.getInt32(at, true);
    case 'uint32':
      return view.getUint32(at, true);
    case 'float32':
      return view.getFloat32(at, true);
    case 'float64':
      return view.getFloat64(at, true);
  }
}

/** Parses `bytes` (a whole PLY file); throws an Error naming what is wrong. */
export function readPly(bytes: Uint8Array): Ply {
  const end = headerEnd(bytes);
  const header = new TextDecoder('latin1').decode(bytes.subarray(0, end)).split('\n').map((l) => l.trim());
  if (header[0] !== 'ply') throw new Error('PLY: the file does not start with "ply"');
  const comments: string[] = [];
  const decls: { name: string; count: number; properties: PropertyDecl[] }[] = [];
  for (const line of header.slice(1)) {
    const words = line.split(/\s+/);
    switch (words[0]) {
      case 'format':
        if (words[1] !== 'binary_little_endian') throw new Error(`PLY: only binary_little_endian is read, not ${words[1]}`);
        break;
      case 'comment':
        comments.push(line.slice('comment'.length).trim());
        break;
      case 'element': {
        const count = Number(words[2]);
        if (!Number.isInteger(count) || count < 0) throw new Error(`PLY: bad element count in "${line}"`);
        decls.push({ name: words[1] ?? '', count, properties: [] });
        break;
      }
      case 'property': {
        const element = decls[decls.length - 1];
        if (!element) throw new Error(`PLY: property before any element: "${line}"`);
        if (words[1] === 'list') element.properties.push({ name: words[4] ?? '', countType: scalarType(words[2], line), type: scalarType(words[3], line) });
        else element.properties.push({ name: words[2] ?? '', type: scalarType(words[1], line) });
        break;
      }
      default:
        break; // obj_info, end_header, blank lines
    }
  }
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  let at = end;
  const need = (n: number) => {
    if (at + n > bytes.byteLength) throw new Error('PLY: the file ends before its last element');
  };
  const elements = new Map<string, PlyElement>();
  for (const d of decls) {
    const scalars = new Map<string, Float64Array>();
    const lists = new Map<string, { values: number[]; offsets: Uint32Array }>();
    for (const p of d.properties) {
      if (p.countType) lists.set(p.name, { values: [], offsets: new Uint32Array(d.count + 1) });
      else scalars.set(p.name, new Float64Array(d.count));
    }
    for (let i = 0; i < d.count; i++) {
      for (const p of d.properties) {
        if (p.countType) {
          need(SIZE[p.countType]);
          const n = read(view, at, p.countType);
          at += SIZE[p.countType];
          need(n * SIZE[p.type]);
          const list = lists.get(p.name)!;
          for (let k = 0; k < n; k++, at += SIZE[p.type]) list.values.push(read(view, at, p.type));
          list.offsets[i + 1] = list.values.length;
        } else {
          need(SIZE[p.type]);
          scalars.get(p.name)![i] = read(view, at, p.type);
          at += SIZE[p.type];
        }
      }
    }
    const packed = new Map([...lists].map(([k, l]) => [k, { values: Float64Array.from(l.values), offsets: l.offsets }]));
    elements.set(d.name, { name: d.name, count: d.count, scalars, lists: packed });
  }
  return { comments, elements };
}

/** Where the binary data start: just past the `end_header` line (a whole line: a comment may hold the words). */
function headerEnd(bytes: Uint8Array): number {
  const marker = '\nend_header';
  const limit = Math.min(bytes.length, 1 << 16);
  outer: for (let i = 0; i + marker.length <= limit; i++) {
    for (let k = 0; k < marker.length; k++) if (bytes[i + k] !== marker.charCodeAt(k)) continue outer;
    let j = i + marker.length;
    if (bytes[j] === 0x0d) j++;
    if (bytes[j] !== 0x0a) continue;
    return j + 1;
  }
  throw new Error('PLY: no end_header line in the first 64 KiB');
}
