/**
 * The DOM-side pieces the controller drives (built by bootstrap.ts, stand-ins in unit tests).
 * A module of its own so the controller and the run display can both name it without importing
 * each other.
 */
import type { ExportPanel } from '../io/ExportPanel';
import type { FileBar } from '../io/FileBar';
import type { ErrorBanner } from '../ui/ErrorBanner';
import type { HoverReadout } from '../ui/HoverReadout';
import type { NotesLine } from '../ui/NotesLine';
import type { LivePlot } from '../ui/LivePlot';
import type { ParamPanel } from '../ui/ParamPanel';
import type { ResultPanel } from '../ui/ResultPanel';
import type { StatusLine } from '../ui/StatusLine';
import type { Timeline } from '../ui/Timeline';
import type { ViewControls } from '../ui/ViewControls';
import type { Legend } from '../viewer/Legend';
import type { Viewer } from '../viewer/Viewer';

export interface Parts {
  viewer: Viewer | null;
  /** Scale of the contour-point colours (contour-to-mesh distance). */
  legend: Legend;
  /** Scale of the mesh colours (vertex-to-nearest-contour distance). */
  meshLegend: Legend;
  params: ParamPanel;
  timeline: Timeline;
  status: StatusLine;
  plot: LivePlot;
  result: ResultPanel;
  banner: ErrorBanner;
  files: FileBar;
  exports: ExportPanel;
  view: ViewControls;
  hover: HoverReadout;
  warnings: HTMLElement;
  /** The reader's notes on the current file (how a label map was read): information, below the warnings. */
  notes: NotesLine;
}
