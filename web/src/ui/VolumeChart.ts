/**
 * The Function panel's volume curve as inline SVG, drawn from volumeCurve's layout, and its key.
 * Each cavity takes its tint in the 3D view's other-surfaces key, so one colour means one surface
 * across the app. The chart scales with the column (viewBox), so on a phone it is wider and its
 * labels a little larger, never crowded.
 *
 * `svg[data-testid=function-curve]`; each polyline `data-surface`; each dot `data-surface`,
 * `data-phase`, `data-ml`; each ED/ES ring (`function-curve-marker`) `data-kind`, `data-surface`,
 * `data-phase`.
 */
import { s } from '../lab/svg';
import { tintOf } from '../viewer/OtherSurfacesLayer';
import { h } from './dom';
import { CURVE_BOX, RING, type CurveLayout, type CurveLine, type CurveMarker } from './volumeCurve';

const KIND = { ED: 'end-diastole', ES: 'end-systole' } as const;

/** The chart and its key, for the panel to put in place. */
export function volumeChart(layout: CurveLayout): Element[] {
  const tint = (surface: string) => tintOf(surface, layout.lines.findIndex((l) => l.surface === surface));
  const svg = s(
    'svg',
    { class: 'function-curve', viewBox: `0 0 ${CURVE_BOX.width} ${CURVE_BOX.height}`, 'data-testid': 'function-curve', role: 'img', 'aria-label': 'Cavity volumes (ml) over the phases' },
    ...axes(layout),
    ...layout.lines.flatMap((l) => lineNodes(l, tint(l.surface))),
    ...layout.markers.map((m) => markerNode(m, tint(m.surface))),
    ...layout.markerLabels.map((l) => s('text', { x: l.x, y: l.y, 'text-anchor': 'middle', class: 'mark-label', style: `fill:${l.surfaces.length === 1 ? tint(l.surfaces[0]) : 'currentColor'}` }, l.kind)),
  );
  const key = h(
    'div',
    { class: 'plot-legend function-curve-key' },
    ...layout.lines.flatMap((l) => [h('span', { class: 'swatch', style: `background:${tint(l.surface)}` }), h('span', {}, l.surface)]),
    ...(layout.markers.length > 0 ? [h('span', { class: 'curve-ring' }), h('span', {}, 'ED, ES')] : []),
  );
  return [svg, key];
}

function axes(layout: CurveLayout): SVGElement[] {
  const { plot } = layout;
  const bottom = plot.top + plot.height;
  return [
    ...layout.yTicks.flatMap((t) => [
      s('line', { x1: plot.left - 2, x2: plot.left + plot.width, y1: t.pos, y2: t.pos, class: 'grid' }),
      s('text', { x: plot.left - 4, y: t.pos + 3, 'text-anchor': 'end' }, t.label),
    ]),
    s('text', { x: plot.left - 4, y: plot.top - 5, 'text-anchor': 'end', class: 'unit' }, 'ml'),
    ...layout.xLabels.map((l) => s('text', { x: l.x, y: bottom + 10, 'text-anchor': l.anchor, class: 'phase-label', 'data-index': l.index }, l.text)),
  ];
}

function lineNodes(l: CurveLine, colour: string): SVGElement[] {
  return [
    ...l.segments.map((seg) => s('polyline', { points: seg.map((p) => `${p.x.toFixed(2)},${p.y.toFixed(2)}`).join(' '), stroke: colour, class: 'curve-line', 'data-surface': l.surface })),
    ...l.dots.map((p) =>
      s('circle', { cx: p.x, cy: p.y, r: 2, fill: colour, class: 'curve-dot', 'data-surface': l.surface, 'data-phase': p.phase, 'data-ml': p.ml }, s('title', {}, `${p.phase} · ${l.surface} ${p.ml.toFixed(1)} ml`)),
    ),
  ];
}

function markerNode(m: CurveMarker, colour: string): SVGElement {
  return s(
    'circle',
    { cx: m.x, cy: m.y, r: RING, stroke: colour, class: 'curve-marker', 'data-testid': 'function-curve-marker', 'data-kind': m.kind, 'data-surface': m.surface, 'data-phase': m.phase },
    s('title', {}, `${m.surface} ${KIND[m.kind]} (${m.kind}): ${m.phase} · ${m.ml.toFixed(1)} ml`),
  );
}
