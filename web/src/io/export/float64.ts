/**
 * Doubles as text, spelled exactly as the command line spells them (the core's `fmt_num`): the
 * shortest decimal that reads back as the same double, plain between 1e-5 and 1e15 and in
 * exponent form (`1.5e-7`, `2e15`) outside. One spelling on both sides is what makes a mesh
 * exported from the app and the CLI's mesh of the same contours the same text, digit for digit.
 */
export function f64(v: number): string {
  if (!Number.isFinite(v)) return String(v);
  if (Object.is(v, -0)) return '-0'; // Rust keeps the sign of zero; String(-0) drops it
  const a = Math.abs(v);
  // JavaScript's plain range is wider (1e-6 to 1e21): switch to exponents where Rust does.
  const s = a === 0 || (a >= 1e-5 && a < 1e15) ? String(v) : v.toExponential().replace('e+', 'e');
  return tieUp(v, s);
}

/**
 * When `v` lies exactly halfway between two shortest spellings, JavaScript takes the one with
 * the even last digit and Rust the one farther from zero ("...804.25" is "...804.2" in one and
 * "...804.3" in the other). Such ties need a coarse double (above ~1e10 in magnitude, or a
 * crafted value), never a vertex in mm, but the spelling should not depend on that.
 */
function tieUp(v: number, s: string): string {
  const [mant, exp = '0'] = s.replace('-', '').split('e');
  const dot = mant.indexOf('.');
  const digits = mant.replace('.', '');
  const q = Number(exp) - (dot < 0 ? 0 : mant.length - dot - 1); // |s| = digits x 10^q
  // A tie is |v| = (odd / 2) x 10^q, so 2|v| / 2^q is an odd whole number: a cheap, exact test
  // (scaling by a power of two loses nothing short of overflow) that rules out almost every value
  // before the exact one.
  const y = 2 * Math.abs(v) * 2 ** -q;
  if (Number.isFinite(y) && (!Number.isInteger(y) || y % 2 !== 1)) return s;
  if (!isExactly(Math.abs(v), 2n * BigInt(digits) + 1n, q)) return s;
  const up = increment(s);
  return up !== null && Number(up) === v ? up : s;
}

/** Whether `a` (a finite double) is exactly (c / 2) x 10^q. */
function isExactly(a: number, c: bigint, q: number): boolean {
  const view = new DataView(new ArrayBuffer(8));
  view.setFloat64(0, a);
  const bits = view.getBigUint64(0);
  const biased = Number((bits >> 52n) & 0x7ffn);
  const fraction = bits & ((1n << 52n) - 1n);
  const m = biased === 0 ? fraction : fraction | (1n << 52n);
  const e = (biased === 0 ? -1074 : biased - 1075) + 1; // 2a = m x 2^e
  // m x 2^e == c x 10^q, both sides made whole.
  const left = m * 2n ** BigInt(Math.max(e, 0)) * 10n ** BigInt(Math.max(-q, 0));
  const right = c * 2n ** BigInt(Math.max(-e, 0)) * 10n ** BigInt(Math.max(q, 0));
  return left === right;
}

/** `s` with its last significant digit one higher (carrying); null if the carry runs off the front. */
function increment(s: string): string | null {
  const end = s.includes('e') ? s.indexOf('e') : s.length;
  const chars = s.split('');
  for (let i = end - 1; i >= 0; i--) {
    if (chars[i] === '.') continue;
    if (chars[i] === '-') return null;
    if (chars[i] !== '9') {
      chars[i] = String(Number(chars[i]) + 1);
      return chars.join('');
    }
    chars[i] = '0';
  }
  return null;
}
