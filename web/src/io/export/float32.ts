/**
 * Float32 values as text: the shortest decimal that reads back as the same float32. The worker
 * hands positions over as Float32Array, and writing them as doubles prints the float32 rounding
 * ("-32.8355712890625" for a file's -32.83557): ugly, twice the size, and no more exact.
 */
export function f32(v: number): string {
  if (!Number.isFinite(v)) return String(v);
  const x = Math.fround(v);
  for (let p = 1; p < 9; p++) {
    const s = x.toPrecision(p);
    if (Math.fround(Number(s)) === x) return String(Number(s));
  }
  return String(Number(x.toPrecision(9))); // 9 significant digits always round-trip a float32
}
