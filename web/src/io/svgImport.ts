/**
 * An SVG document as text (the core's AHA bullseye) turned into nodes of this page, never through
 * innerHTML: parsed as image/svg+xml (a stray `<` is then an error, not markup guessed at) and
 * imported. It is our own output, but the page must not depend on that: scripts, foreign objects,
 * event-handler attributes and links leaving the drawing are dropped. Its ids get a prefix so that
 * a gradient of this drawing never resolves to another one's of the same id on the page.
 */

const SVG_NS = 'http://www.w3.org/2000/svg';

/** Attributes that can refer to an id (`url(#viridis)`, `#viridis`). */
const REFERRING = /url\(#([^)]+)\)/g;

/**
 * The SVG of `text` as an element of this document (not yet attached), its ids prefixed with
 * `idPrefix`; null when the text is not an SVG document.
 */
export function importSvg(text: string, idPrefix: string): SVGSVGElement | null {
  const doc = new DOMParser().parseFromString(text, 'image/svg+xml');
  const root = doc.documentElement;
  if (!root || root.namespaceURI !== SVG_NS || root.localName !== 'svg') return null;
  if (doc.getElementsByTagName('parsererror').length > 0) return null;
  for (const el of Array.from(root.querySelectorAll('script, foreignObject'))) el.remove();
  const all = [root, ...Array.from(root.querySelectorAll('*'))];
  const ids = new Map<string, string>();
  for (const el of all) {
    const id = el.getAttribute('id');
    if (id) ids.set(id, `${idPrefix}-${id}`);
  }
  const renamed = (id: string) => ids.get(id) ?? id;
  for (const el of all) {
    for (const attr of Array.from(el.attributes)) {
      const name = attr.name.toLowerCase();
      if (name.startsWith('on')) el.removeAttribute(attr.name);
      else if (name === 'id') el.setAttribute(attr.name, renamed(attr.value));
      else if (name === 'href' || name === 'xlink:href') {
        // Only references inside the drawing: no navigation, no resources fetched.
        if (attr.value.startsWith('#')) el.setAttribute(attr.name, `#${renamed(attr.value.slice(1))}`);
        else el.removeAttribute(attr.name);
      } else if (attr.value.includes('url(#')) {
        el.setAttribute(attr.name, attr.value.replace(REFERRING, (_, id: string) => `url(#${renamed(id)})`));
      }
    }
  }
  return document.importNode(root, true) as unknown as SVGSVGElement;
}
