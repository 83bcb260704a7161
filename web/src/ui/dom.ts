/** Tiny DOM helpers: the UI is plain DOM (no framework) to keep the bundle small and offline-safe. */

type Attrs = Record<string, string | number | boolean | null | undefined>;

/** Creates an element with attributes (`class`, `data-*`, `aria-*`, ...) and children. */
export function h<K extends keyof HTMLElementTagNameMap>(
  tag: K,
  attrs: Attrs = {},
  ...children: (Node | string | null | undefined)[]
): HTMLElementTagNameMap[K] {
  const el = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (v === null || v === undefined || v === false) continue;
    el.setAttribute(k, v === true ? '' : String(v));
  }
  for (const c of children) if (c !== null && c !== undefined) el.append(c);
  return el;
}

/** Formats a distance in mm with sensible precision. */
export function mm(v: number, digits = 2): string {
  return Number.isFinite(v) ? `${v.toFixed(digits)} mm` : '– mm';
}
