/**
 * Builds the parts of the page, mounts them into index.html's slots and wires them to the
 * controller. Separate from main.ts so the visual test harness can start the same page with a
 * synthetic core (tests/visual/).
 */
import '../styles.css';
import { version as appVersion } from '../../../package.json';
import { Controller, type Parts } from './controller';
import type { CoreClient } from '../core-client/CoreClient';
import { installDropZone } from '../io/dropZone';
import { LabPanel } from '../lab/LabPanel';
import { ExportPanel } from '../io/ExportPanel';
import { FileBar } from '../io/FileBar';
import { installKeyboard } from '../ui/keyboard';
import { ContourTable } from '../ui/ContourTable';
import { ErrorBanner } from '../ui/ErrorBanner';
import { FunctionPanel } from '../ui/FunctionPanel';
import { HoverReadout } from '../ui/HoverReadout';
import { NotesLine } from '../ui/NotesLine';
import { LivePlot } from '../ui/LivePlot';
import { ParamPanel } from '../ui/ParamPanel';
import { ResultPanel } from '../ui/ResultPanel';
import { StatusLine } from '../ui/StatusLine';
import { Timeline } from '../ui/Timeline';
import { ViewControls } from '../ui/ViewControls';
import { Legend } from '../viewer/Legend';
import { Viewer } from '../viewer/Viewer';

function slot(id: string): HTMLElement {
  const el = document.getElementById(id);
  if (!el) throw new Error(`index.html lacks #${id}`);
  return el;
}

export function bootstrap(createClient: () => Promise<CoreClient>): Controller {
  let controller: Controller;
  const c = () => controller;
  const viewport = slot('slot-viewport');
  let viewer: Viewer | null = null;
  try {
    viewer = new Viewer(viewport);
  } catch {
    viewport.classList.add('no-webgl');
    viewport.append(Object.assign(document.createElement('p'), { className: 'no-webgl-note', textContent: '3D view unavailable: this browser has WebGL disabled. Reconstruction, numbers and exports still work.' }));
  }

  const parts: Parts = {
    viewer,
    legend: new Legend('contour points: distance to mesh', 'legend-contours'),
    meshLegend: new Legend('mesh: distance to nearest contour', 'legend-mesh'),
    params: new ParamPanel((v, lids, options) => c().setParams(v, lids, options), () => c().resetParams()),
    timeline: new Timeline({
      togglePlay: () => c().togglePlay(),
      step: (d) => c().step(d),
      seek: (i) => c().seek(i),
      first: () => c().first(),
      latest: () => c().latestStep(),
      setSpeed: (s) => c().setSpeed(s),
      rerun: () => c().startRun(),
      stop: () => c().stopRun(),
    }),
    status: new StatusLine(),
    plot: new LivePlot(),
    // Its "align" button (images that disagree where they cross) ticks the parameter panel's option.
    result: new ResultPanel(() => parts.params.alignBreathHolds()),
    banner: new ErrorBanner(),
    files: new FileBar({
      openFiles: (f) => void c().openFiles(f),
      openFolder: (f) => void c().openFolder(f),
      trySample: (s) => void c().trySample(s),
      chooseFile: (n) => c().chooseFile(n),
      chooseSurface: (s) => c().chooseSurface(s),
      runAllSurfaces: () => c().runAllSurfaces(),
      chooseFrame: (f) => c().chooseFrame(f),
    }),
    exports: new ExportPanel({
      info: () => c().exportInfo(),
      result: () => c().currentResult(),
      screenshot: () => c().screenshot(),
      session: () => c().sessionFile(),
      others: () => c().otherSurfaceMeshes(),
      wallFile: (format) => c().wallFile(format),
      bivWallFile: (format) => c().bivWallFile(format),
      failed: (e) => c().showExportError(e),
      showWall: (id, wall) => c().showWall(id, wall),
      hideWall: () => c().hideWall(),
      anatomicalFile: (layout, format, header) => c().anatomicalFile(layout, format, header),
      showAnatomical: (built) => c().showAnatomical(built),
      hideAnatomical: () => c().hideAnatomical(),
      hexFile: (layout, header) => c().hexFile(layout, header),
    }),
    view: new ViewControls((v) => c().setView(v), () => c().resetView(), (colouring) => c().setWallColouring(colouring)),
    hover: new HoverReadout(),
    warnings: slot('slot-warnings'),
    notes: new NotesLine(),
  };
  controller = new Controller(parts, appVersion);

  slot('slot-filebar').append(parts.files.element);
  slot('slot-left').append(parts.params.element);
  // The phases of one heart measured together (EDV/ESV/EF, LV mass), beside the run on screen.
  const fn = new FunctionPanel({
    context: () => controller.functionContext(),
    onContextChange: (l) => controller.onContextChange(l),
    client: () => controller.coreClient,
  });
  // Each contour's distance to the mesh, to leave one out by hand; its rows and the 3D view highlight each other.
  const contours = new ContourTable({
    context: () => controller.contourContext(),
    setLeftOut: (id, out) => controller.setLeftOut(id, out),
    useAll: () => controller.useAllContours(),
    highlight: (id) => viewer?.highlightContour(id),
    exportInfo: () => controller.exportInfo(),
  });
  controller.onResult((r) => (r ? contours.show(r) : contours.resultCleared()));
  controller.onLeaveOutChange(() => contours.leaveOutChanged());
  slot('slot-right').append(parts.status.element, parts.plot.element, parts.result.element, contours.element, parts.exports.element, fn.element);
  slot('slot-bottom').append(parts.timeline.element);
  slot('slot-banner').append(parts.banner.element);
  slot('slot-notes').append(parts.notes.element);
  slot('slot-legend').append(parts.legend.element, parts.meshLegend.element);
  if (viewer) slot('slot-legend').append(viewer.landmarkLayer.legend, viewer.setAsideLayer.legend, viewer.otherSurfacesLayer.legend, viewer.wallLayer.thicknessLegend.element, viewer.wallLayer.regionKey);
  slot('slot-viewcontrols').append(parts.view.element);
  slot('slot-hover').append(parts.hover.element);
  viewer?.setHoverListener((h) => {
    controller.onHover(h);
    contours.hoverFromView(h && (h.what === 'contour point' || h.what === 'left out') ? (h.id ?? null) : null);
  });

  const lab = new LabPanel({ controller, viewer, legendSlot: slot('slot-legend') });
  lab.mount(slot('slot-left'), parts.params.element);

  installDropZone(document.body, slot('drop-overlay'), (files, skipped) => lab.claimDrop(files) || void controller.openFiles(files, skipped), () => controller.waitsForImages);
  installKeyboard(document, {
    togglePlay: () => controller.togglePlay(),
    step: (d) => controller.step(d),
    first: () => controller.first(),
    latest: () => controller.latestStep(),
    resetView: () => controller.resetView(),
    stop: () => controller.stopRun(),
  });

  void controller.start(createClient);
  (window as unknown as { heartmesh: Controller }).heartmesh = controller;
  // For the browser tests: where a point is drawn (Viewer.screenPosition), to hover over it.
  (window as unknown as { heartmeshViewer: Viewer | null }).heartmeshViewer = viewer;
  return controller;
}
