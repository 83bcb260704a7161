/**
 * Inline SVG icons (no icon font, no emoji: they render the same everywhere, even on systems
 * without symbol fonts, and nothing is fetched).
 */
const PATHS = {
  play: 'M5 3l9 5-9 5z',
  pause: 'M4 3h3v10H4zM9 3h3v10H9z',
  back: 'M11 3v10L4 8z',
  forward: 'M5 3v10l7-5z',
  first: 'M3 3h2v10H3zM13 3v10L6 8z',
  latest: 'M11 3h2v10h-2zM3 3v10l7-5z',
  lock: 'M5 7V5a3 3 0 016 0v2h1v7H4V7zm2 0h2V5a1 1 0 00-2 0z',
  stop: 'M4 4h8v8H4z',
  restart: 'M8 3a5 5 0 11-4.6 3H1.5L4.5 2l3 4H5.6A3 3 0 108 5z',
  folder: 'M1 3.5A1.5 1.5 0 012.5 2h3.4l1.5 1.5h6.1A1.5 1.5 0 0115 5v7.5a1.5 1.5 0 01-1.5 1.5h-11A1.5 1.5 0 011 12.5z',
} as const;

export type IconName = keyof typeof PATHS;

export function icon(name: IconName): SVGSVGElement {
  const ns = 'http://www.w3.org/2000/svg';
  const svg = document.createElementNS(ns, 'svg');
  svg.setAttribute('viewBox', '0 0 16 16');
  svg.setAttribute('width', '14');
  svg.setAttribute('height', '14');
  svg.setAttribute('aria-hidden', 'true');
  svg.classList.add('icon-svg');
  const path = document.createElementNS(ns, 'path');
  path.setAttribute('d', PATHS[name]);
  path.setAttribute('fill', 'currentColor');
  path.setAttribute('fill-rule', 'evenodd');
  svg.append(path);
  return svg;
}
