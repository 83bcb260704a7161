/**
 * Getting data in: the Open button (a real `<input type="file">` accepting the canonical CSV, the
 * other contour formats and NIfTI label maps) and its folder button (`webkitdirectory`: a cvi42
 * study's folder, a biv-me patient's), "Try an example" buttons, the picker of loaded files, the surface
 * picker for files holding several surfaces and the frame picker for files holding a sequence of
 * time frames (app/timeFrames.ts decides its options).
 */
import type { FramePicker } from '../app/timeFrames';
import { h } from '../ui/dom';
import { icon } from '../ui/icons';
import { SAMPLES, type Sample } from './samples';

/**
 * The contour formats the core reads (canonical CSV first; see README "Files"), and NIfTI label
 * maps (segmentations, `.nii` or `.nii.gz`; 3D Slicer's `.nrrd` / `.seg.nrrd`; DICOM SEG `.dcm`). A bare `.gz` too: the core reads any of these
 * formats gzip-compressed (`contours.csv.gz`), not every file dialog filters on a two-part
 * extension, and the core names what it cannot read in a compressed file the user chose. A Circle
 * cvi42 workspace (`.cvi42wsx`), opened with the DICOM images it was drawn on (io/cvi42Study.ts).
 * ZIP archives (`.zip`, UK Biobank's): unpacked in the page, their files opened (io/zipArchive.ts).
 */
export const ACCEPT = '.csv,.txt,.tsv,.dat,.xyz,.vtk,.vtp,.mat,.json,.dcm,.nii,.nii.gz,.nrrd,.gz,.cvi42wsx,.zip,.mrb,.mrml,.fcsv,text/csv,text/plain,application/dicom';

export interface FileBarHandlers {
  openFiles(files: File[]): void;
  /** Every file under a picked folder (`webkitRelativePath` set); the controller chooses which open. */
  openFolder(files: File[]): void;
  trySample(sample: Sample): void;
  chooseFile(fileName: string): void;
  chooseSurface(surface: string): void;
  /** Reconstructs every surface of the file in turn (the "All" button beside the surface picker). */
  runAllSurfaces(): void;
  /** A `FrameOption.value` of the frame picker. */
  chooseFrame(frame: string): void;
}

export class FileBar {
  readonly element: HTMLElement;
  readonly input: HTMLInputElement;
  /** The folder picker (`webkitdirectory`): a study's folder holds images without extensions the Open dialog hides. */
  readonly folderInput: HTMLInputElement;
  private readonly files: HTMLSelectElement;
  private readonly surfaces: HTMLSelectElement;
  private readonly frames: HTMLSelectElement;
  private readonly filesWrap: HTMLElement;
  private readonly surfacesWrap: HTMLElement;
  private readonly framesWrap: HTMLElement;
  private readonly sampleButtons: HTMLButtonElement[] = [];

  constructor(handlers: FileBarHandlers) {
    // Out of the tab order: the Open… label is its keyboard control (a focused hidden input shows no focus).
    this.input = h('input', { type: 'file', accept: ACCEPT, multiple: true, id: 'file-input', 'data-testid': 'file-input', class: 'visually-hidden', tabindex: -1 });
    this.input.addEventListener('change', () => {
      const files = Array.from(this.input.files ?? []);
      this.input.value = '';
      if (files.length) handlers.openFiles(files);
    });
    const open = h('label', { for: 'file-input', class: 'button primary', role: 'button', tabindex: 0, title: 'Open contour files or segmentations (or drop them anywhere)' }, 'Open…');
    open.addEventListener('keydown', (e) => {
      // A Space the shortcuts took as play/pause (the label clicked with the mouse) is not a press.
      if (e.key === ' ' && e.defaultPrevented) return;
      if (e.key === 'Enter' || e.key === ' ') {
        e.preventDefault();
        this.input.click();
      }
    });
    this.folderInput = h('input', { type: 'file', webkitdirectory: true, id: 'folder-input', 'data-testid': 'folder-input', class: 'visually-hidden', tabindex: -1 });
    this.folderInput.addEventListener('change', () => {
      const files = Array.from(this.folderInput.files ?? []);
      this.folderInput.value = '';
      if (files.length) handlers.openFolder(files);
    });
    const folder = h(
      'label',
      { for: 'folder-input', class: 'button primary folder-open', role: 'button', tabindex: 0, 'aria-label': 'Open a folder', 'data-testid': 'open-folder', title: 'Open a folder: a cvi42 study (its .cvi42wsx workspace and the DICOM images it was drawn on), a Sunnybrook case (its contour files and image series), a biv-me patient, a segmented study (or drop the folders anywhere)' },
      icon('folder'),
    );
    folder.addEventListener('keydown', (e) => {
      if (e.key === ' ' && e.defaultPrevented) return;
      if (e.key === 'Enter' || e.key === ' ') {
        e.preventDefault();
        this.folderInput.click();
      }
    });
    const samples = h('div', { class: 'samples' }, h('span', { class: 'muted samples-label' }, 'Try an example:'));
    for (const s of SAMPLES) {
      // Both wordings, the CSS showing one: the short one when pickers crowd the top bar (the
      // accessible name stays the full label).
      const b = h(
        'button',
        { type: 'button', class: 'small', title: s.description, 'aria-label': s.label, 'data-testid': `sample-${s.id}`, 'data-sample': s.id },
        h('span', { class: 'sample-long' }, s.label),
        h('span', { class: 'sample-short' }, s.short),
      );
      b.addEventListener('click', () => handlers.trySample(s));
      this.sampleButtons.push(b);
      samples.append(b);
    }
    this.files = h('select', { 'aria-label': 'Loaded file', 'data-testid': 'file-picker' });
    this.files.addEventListener('change', () => handlers.chooseFile(this.files.value));
    this.surfaces = h('select', { 'aria-label': 'Surface', 'data-testid': 'surface-picker' });
    this.surfaces.addEventListener('change', () => handlers.chooseSurface(this.surfaces.value));
    this.frames = h('select', { 'aria-label': 'Time frame', 'data-testid': 'frame-picker' });
    this.frames.addEventListener('change', () => handlers.chooseFrame(this.frames.value));
    this.files.title = 'Loaded file';
    this.surfaces.title = 'Surface to reconstruct';
    this.frames.title = 'Time frame to reconstruct (the file holds several)';
    this.filesWrap = h('span', { class: 'picker', hidden: true }, this.files);
    const all = h('button', {
      type: 'button', class: 'small', 'data-testid': 'run-all-surfaces',
      title: 'Reconstruct every surface of the file in turn, ending on this one; each is kept, and the view\'s Other surfaces shows them together',
    }, 'All');
    all.addEventListener('click', () => handlers.runAllSurfaces());
    this.surfacesWrap = h('span', { class: 'picker', hidden: true }, this.surfaces, all);
    this.framesWrap = h('span', { class: 'picker', hidden: true }, this.frames);
    this.element = h('div', { class: 'filebar' }, this.input, this.folderInput, h('span', { class: 'open-group' }, open, folder), samples, this.filesWrap, this.surfacesWrap, this.framesWrap);
  }

  setFiles(names: string[], current: string | null): void {
    this.files.replaceChildren(...names.map((n) => h('option', { value: n }, n)));
    if (current) this.files.value = current;
    this.filesWrap.hidden = names.length < 2;
  }

  setSurfaces(surfaces: string[], current: string | null): void {
    this.surfaces.replaceChildren(...surfaceOrder(surfaces).map((s) => h('option', { value: s }, surfaceLabel(s))));
    if (current) this.surfaces.value = current;
    this.surfacesWrap.hidden = surfaces.length < 2;
  }

  /** The frames of the current file (null: it holds one phase, no picker). */
  setFrames(picker: FramePicker | null): void {
    const options = picker?.options ?? [];
    this.frames.replaceChildren(
      ...options.map((o) => h('option', { value: o.value, disabled: o.disabled, ...(o.title ? { title: o.title } : {}) }, o.label)),
    );
    if (picker) this.frames.value = picker.value;
    this.framesWrap.hidden = picker === null;
  }
}

const SURFACE_LABELS: Record<string, string> = {
  LV_ENDO: 'LV endocardium',
  LV_EPI: 'LV epicardium',
  RV_ENDO: 'RV endocardium',
  RV_EPI: 'RV epicardium',
  BIV_EPI: 'BiV epicardium',
};

/**
 * The picker's order: LV endo, LV epi, RV endo, RV epi, the biventricular epicardium the core
 * makes of the two epicardia, then any other surface in the file's order
 * (files list them in whatever order their curves come, e.g. RV first).
 */
export function surfaceOrder(surfaces: readonly string[]): string[] {
  const known = Object.keys(SURFACE_LABELS);
  const rank = (s: string) => (known.includes(s) ? known.indexOf(s) : known.length);
  return surfaces.map((s, i) => ({ s, i })).sort((a, b) => rank(a.s) - rank(b.s) || a.i - b.i).map(({ s }) => s);
}

export function surfaceLabel(s: string): string {
  return SURFACE_LABELS[s] ?? s;
}
