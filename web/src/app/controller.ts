/**
 * Wires the core client, the viewer and the UI together. Owns the application state (the pure
 * machine in state.ts), the loaded files, the parameters (mirrored in the URL), the running
 * reconstruction. All heavy work happens in the worker; this class only routes data. What a run
 * puts on screen (recorded frames, playback, result colours, contours), decided once per animation
 * frame, is runDisplay.ts; the DOM parts it drives are named in parts.ts.
 */
import type { CoreClient } from '../core-client/CoreClient';
import type {
  AnatomicalFormat, ContourKindName, CoreErrorData, PhaseSpec, Frame, LabelMapGrid, LidsMode, LoadedFile, ParamSpec, ParamValues, ReconOptions, RunResult, SessionSettings, ViewFile, WallFormat, WallSummary, AnatomicalSummary,
} from '../core-client/protocol';
import { DEFAULT_OPTIONS, withDefaultOptions } from '../core-client/protocol';
import type { ExportInfo } from '../io/export/header';
import { findSample, fetchSample, type Sample } from '../io/samples';
import type { HoverReadout } from '../ui/HoverReadout';
import { distinctName, fileIdentity, lostText, renamedText, skippedText } from './fileNames';
import { archivesText, asCoreError, callSafely, imagesAsideText, isDicomImageRefusal, isImageRefusal, isSliceInfoRefusal, keptText, schemaOrdered, setAsideText, unreadable, viewRefusal } from './errors';
import { addedViewsText, assignViews, byName, isSingleSlice, isStack } from '../io/studyGroups';
import { asksForImages, cvi42Study, workspaceTest, type Cvi42Study } from '../io/cvi42Study';
import { pairSliceInfo, sliceInfoReadText } from '../io/gpStudy';
import { imageHeaders, isSegmentationFile, looksDicom } from '../io/dicomHeaders';
import { filesOfPickedFolder, folderOfFile, pathInFolder, withSegmentations } from '../io/folderDrop';
import { expandArchives } from '../io/zipArchive';
import { joinMarkups, joinedText } from '../io/markupsStudy';
import { sceneAsideText, sceneOf } from '../io/slicerScene';
import type { Parts } from './parts';
import type { Speed } from './playback';
import { keptSpecksNote, secondLoopsNote } from '../ui/runText';
import { warningsFor } from './fileWarnings';
import { RunDisplay } from './runDisplay';
import { surfacePoints } from './sceneContours';
import { frameChoice, framePicker, frameToRead, missingFrameNote, namedFrame, sameFrame } from './timeFrames';
import { canStop, currentRunId, describeError, initialState, isComputing, loadedFile, statusWord, transition, type AppEvent, type AppState } from './state';
import { defaultParams, parseUrlState, serializeUrlState, DEFAULT_VIEW, type ViewSettings } from './urlState';
import { KeptSurfaces, runSignature, settingsKey, type KeptMesh } from './keptSurfaces';
import { LeaveOutLists, leaveOutKeyPart, type LeaveOutKey } from './leaveOut';
import { WALL_MIN_THICKNESS_MM, wallHeaderLines, wallReadiness, type WallReadiness } from '../io/export/wall';
import { bivWallHeaderLines, bivWallReadiness, type BivWallReadiness } from '../io/export/bivWall';
import { surfaceOrder } from '../io/FileBar';
import { BIV_EPI, partOf } from '../core-client/derivedSurfaces';
import { phasesOf } from './phases';
import { wallSolidFromPly } from '../io/wallSolid';
import type { BuiltWall } from '../io/WallRow';
import type { BuiltAnatomical } from '../io/AnatomicalRow';
import { anatomicalHeaderLines, type AnatomicalLayout } from '../io/export/anatomical';
import { hexHeaderLines, type HexLayout } from '../io/export/hexWall';
import type { BuiltHex } from '../io/HexRow';
import type { WallColouring } from '../viewer/wallColours';
import type { FunctionContext } from '../ui/FunctionPanel';
import { leftOutNote } from '../ui/functionText';

export type { Parts } from './parts';

/** Bytes that tell whether a file may be a label map (DICOM's magic is at 128). */
const LABEL_MAP_HEAD = 132;

/**
 * Whether bytes (the first `LABEL_MAP_HEAD` are enough) may be a label map: a NIfTI-1 (gzip's
 * magic, or the header size 348 in either byte order), a NRRD (its magic), or a DICOM file (a
 * segmentation is one; an image is not, which the core says). Anything else is no label map and
 * costs the core no question.
 */
function mayBeLabelMap(bytes: ArrayBuffer): boolean {
  if (bytes.byteLength < 4) return false;
  const head = new DataView(bytes, 0, 4);
  const nrrd = String.fromCharCode(...new Uint8Array(bytes, 0, 4)) === 'NRRD';
  const nifti = (head.getUint8(0) === 0x1f && head.getUint8(1) === 0x8b) || head.getInt32(0, true) === 348 || head.getInt32(0, false) === 348;
  return nifti || nrrd || looksDicom(new Uint8Array(bytes, 0, Math.min(bytes.byteLength, LABEL_MAP_HEAD)));
}

/** Whether two readings are of the same frame (null: a file's only reading, or each contour's first). */
function sameReading(a: string | null, b: string | null): boolean {
  return a === null || b === null ? a === b : sameFrame(a, b);
}

/** Said of a stack refused because of a long-axis view read with it. */
const stackNotOpened = (stack: string) => `Its stack ${stack} is not opened either`;


/** Delay between the last parameter change and the restart of the run. */
export const RESTART_DEBOUNCE_MS = 300;

interface ActiveRun {
  runId: number;
  cancel(): void;
  /** What it was run with (`settingsKey`): its mesh is kept with it. */
  settings: string;
}

/** A file of those opened together: its grid if a label map, its bytes if kept meanwhile. */
interface Opened {
  file: File;
  grid: LabelMapGrid | null;
  bytes: ArrayBuffer | null;
  /** Why its bytes could not be read (absent: they were). */
  unreadable?: unknown;
}

export class Controller {
  private state: AppState = initialState;
  private client: CoreClient | null = null;
  private schema: ParamSpec[] = [];
  private coreVersion = '';
  private readonly files = new Map<string, LoadedFile>();
  /** What each open name stands for (fileNames.ts): a different file of that name gets another. */
  private readonly identities = new Map<string, string>();
  /** The open files that are short-axis label-map stacks: long-axis views opened alone are added to one on screen. */
  private readonly stacks = new Set<string>();
  private params: ParamValues = {};
  private lids: LidsMode = 'auto';
  private options: ReconOptions = { ...DEFAULT_OPTIONS };
  /** The current file's load-time warnings (and a note on a surface it lacks), as the warning line shows them. */
  private fileWarnings: string[] = [];
  /** The current run's note from the core (its mesh will reach the remesh cap), shown with the warnings. */
  private runNote: string | null = null;
  private surface: string | null = null;
  /**
   * The time frame asked for by its label (the Frame picker's, or the link's: `9`, `ES`): read of
   * every file holding a sequence that has it, as the surface is picked of every file; null: each
   * file's own first.
   */
  private frame: string | null = null;
  /** Bumped by each frame reload: the answer of one overtaken by another is not shown. */
  private frameToken = 0;
  private sampleId: string | null = null;
  private view: ViewSettings = { ...DEFAULT_VIEW };
  /** The file's finished surfaces (last run of each): the other-surfaces view and the all-surfaces export. */
  private readonly kept = new KeptSurfaces();
  /** Surfaces still to run after the current one for "All" (empty: none queued). */
  private allQueue: string[] = [];
  private active: ActiveRun | null = null;
  /** The run on screen: recorded frames, playback, result, contours (runDisplay.ts). */
  private readonly runView: RunDisplay;
  /** A run that failed while a file was being read: reported with the file's outcome. */
  private pendingRunFailure: CoreErrorData | null = null;
  /**
   * Contours refused for want of their images (a cvi42 workspace, a Sunnybrook contours folder):
   * the next files opened are tried as them.
   */
  private waitingStudy: Cvi42Study<File> | null = null;
  /** Why the last file read was refused (openFiles names every refused file of a drop). */
  private lastRefusal: CoreErrorData | null = null;
  private restartTimer: ReturnType<typeof setTimeout> | null = null;
  /** Resolves once the core answered (true) or failed to start (false); input waits for it. */
  private readonly ready: Promise<boolean>;
  private markReady: (ok: boolean) => void = () => undefined;
  private coreUp = false;
  private readonly resultListeners: ((r: RunResult | null) => void)[] = [];
  private readonly contextListeners: (() => void)[] = [];
  /** Per open file, how many times it was read anew (dropped again, views added): the Function table's contours. */
  private readonly readings = new Map<string, number>();
  /** What colours a wall shown in the view (the view panel's Wall colour): kept from one wall to the next. */
  /** The contours the user left out, one list per file and frame, every surface's (the Contours panel; never in the URL). */
  private readonly leftOut = new LeaveOutLists();
  private readonly leaveOutListeners: (() => void)[] = [];

  constructor(
    private readonly parts: Parts,
    private readonly appVersion: string,
  ) {
    this.ready = new Promise((resolve) => (this.markReady = resolve));
    this.runView = new RunDisplay(parts, {
      currentFile: () => this.currentFile(),
      surface: () => this.surface,
      iterations: () => this.params.iterations,
    });
  }

  // ---- start-up -------------------------------------------------------------------------------

  /** Connects the core; reads the URL; loads the sample the URL names. */
  async start(createClient: () => Promise<CoreClient>): Promise<void> {
    this.parts.view.show(this.view);
    this.setStatus();
    this.runView.startLoop();
    try {
      this.client = await createClient();
      const { schema, version } = await this.client.schema();
      this.schema = schema;
      this.coreVersion = version;
    } catch (e) {
      const err = asCoreError(e, 'the WebAssembly core could not start');
      this.fail({ ...err, code: err.code === 'worker_crashed' ? 'core_unavailable' : err.code });
      this.markReady(false);
      return;
    }
    this.coreUp = true;
    const url = parseUrlState(location.search, this.schema);
    this.params = url.params;
    this.lids = url.lids;
    this.options = url.options;
    // The link's surface is the one wanted for any file opened later (dropped, picked, a sample),
    // not only for the sample the link names: selectFile falls back, with a notice, when absent.
    this.surface = url.surface;
    this.frame = url.frame;
    this.view = url.view;
    this.parts.params.setSchema(this.schema);
    this.parts.params.setValues(this.params, this.lids, this.options);
    this.parts.view.show(this.view);
    this.applyView();
    this.setStatus();
    this.markReady(true);
    const sample = findSample(url.sample);
    if (sample) await this.trySample(sample, url.surface);
  }

  // ---- loading --------------------------------------------------------------------------------

  /**
   * Opens dropped or chosen files; `skipped`: files of dropped folders not handed over (not of a
   * kind the app reads, or past the folder limit), said in the banner so nothing goes unmentioned.
   * Label maps (NIfTI, NRRD, DICOM SEG) of a single slice among them are long-axis views: each is read with the
   * short-axis stack of the same files whose name it resembles most (io/studyGroups.ts), not on
   * its own; with no stack among the files, they are added to the stack on screen, if it is one.
   * ZIP archives among them (UK Biobank's) are replaced by their files first (io/zipArchive.ts).
   */
  async openFiles(given: File[], skipped = 0): Promise<void> {
    if (given.length === 0) return;
    // Say "loading" at once, before the bytes are read (and before the core is up, if it is not).
    // A run in progress goes on until a file has been read: a refused file leaves the work as it was
    // (unless the file would wait behind a step of seconds: see loadBytes).
    this.dispatch({ type: 'load', fileName: given[0].name });
    if (!(await this.ready)) return;
    // The files of ZIP archives instead of the archives (DICOM images as their headers); an
    // archive that cannot be read (damaged, encrypted, too big unpacked) is named, not opened.
    const unpacked = await expandArchives(given);
    let files: File[] = unpacked.files;
    const archivesRefused = unpacked.refused;
    if (files.length === 0) {
      // Nothing but archives, none read: the first refused, the others named after it.
      const [one, ...others] = archivesRefused;
      if (one) this.refuse(one.file ?? given[0].name, one, others.length > 0 ? ` ${archivesText(others)}` : '');
      return;
    }
    // A cvi42 workspace (Sunnybrook contour files) among them: every other file is one of its images (io/cvi42Study.ts).
    const study = cvi42Study(files, await workspaceTest(files));
    if (study) return void (await this.openStudy(study, skipped, false, archivesRefused));
    // Contours just refused for want of their images: these files may be them (else, as usual).
    const waiting = this.waitingStudy;
    this.waitingStudy = null;
    if (waiting && (await this.openStudy({ workspaces: waiting.workspaces, images: [...waiting.images, ...files] }, skipped, true, archivesRefused))) return;
    // A Slicer scene (its folder or .mrb bundle): its curves, else its segmentations; the scene
    // file and the rest set aside, named (io/slicerScene.ts).
    const scene = await sceneOf(files);
    if (scene) files = scene.files;
    // Slicer markups, a file per curve: joined into one set (io/markupsStudy.ts).
    const markups = await joinMarkups(files, folderOfFile);
    files = markups.files;
    // biv-me folders: each GPFile read with the SliceInfoFile beside it (io/gpStudy.ts).
    const gp = await pairSliceInfo(files, folderOfFile);
    files = gp.files;
    const sliceInfoRead: { gp: string; info: string }[] = [];
    const onScreen = this.currentFile()?.fileName ?? null;
    let first: string | null = null;
    // The archives not read count among the files not opened, as any file refused.
    const refused: CoreErrorData[] = [...archivesRefused];
    const count = files.length + archivesRefused.length;
    /** How many of the files each refusal stands for (a stack refused with its views: all of them). */
    const refusedFiles = new Map<CoreErrorData, number>();
    /** The stacks refused because of a view read with them (the refusal names the view). */
    const refusedStacks = new Map<CoreErrorData, string>();
    const renamed: { given: string; as: string }[] = [];
    const opened = await this.readFiles(files);
    const stacks = opened.filter((o) => isStack(o.grid));
    const views = opened.filter((o) => isSingleSlice(o.grid));
    const home = assignViews(stacks.map((o) => o.file.name), views.map((o) => o.file.name));
    const viewsOf = (stack: Opened): ViewFile[] =>
      byName(views.filter((_, v) => home[v] === stacks.indexOf(stack)).map((v) => ({ name: v.file.name, bytes: v.bytes as ArrayBuffer })));
    // Views with no stack among the files: onto the stack on screen, else each opened alone (the core says it needs its stack).
    const target = stacks.length === 0 && views.length > 0 && onScreen !== null && this.stacks.has(onScreen) ? onScreen : null;
    for (const o of opened) {
      if ('unreadable' in o) {
        // The file went away (moved, no permission) between the drop and the read, or is a folder.
        refused.push(this.refuse(o.file.name, unreadable(o.file, o.unreadable)));
        continue;
      }
      if (isSingleSlice(o.grid) && (stacks.length > 0 || target !== null)) continue; // read with its stack
      const bytes = o.bytes ?? (await this.bytesOf(o.file, refused));
      if (bytes === null) continue;
      // Another patient's GPFile_000.txt (or two of them in one drop) is kept beside the first.
      const identity = fileIdentity(o.file);
      const name = distinctName(o.file.name, identity, this.identities);
      const withViews = isStack(o.grid) ? viewsOf(o) : await this.sliceInfoOf(gp.sliceInfo.get(o.file), refused);
      if (await this.loadBytes(name, bytes, identity, withViews, o.grid)) {
        first ??= name;
        if (!isStack(o.grid)) sliceInfoRead.push(...withViews.map((v) => ({ gp: name, info: v.name })));
        if (name !== o.file.name) renamed.push({ given: o.file.name, as: name });
      } else if (this.lastRefusal) {
        refused.push(this.lastRefusal);
        refusedFiles.set(this.lastRefusal, 1 + (isStack(o.grid) ? withViews.length : 0));
        if (withViews.some((v) => v.name === this.lastRefusal?.file)) refusedStacks.set(this.lastRefusal, name);
      }
    }
    let added = '';
    if (target !== null) {
      const loose = views.map((v) => ({ name: v.file.name, bytes: v.bytes as ArrayBuffer }));
      if (await this.addViews(target, loose)) {
        first ??= target;
        added = addedViewsText(loose.map((v) => v.name), target);
      } else if (this.lastRefusal) {
        refused.push(this.lastRefusal);
        refusedFiles.set(this.lastRefusal, loose.length);
      }
    }
    const joinedNote = markups.names.length > 0 && first !== null ? joinedText(markups.joined, markups.names) : '';
    const sceneNote = scene && scene.aside.length > 0 && first !== null ? sceneAsideText(scene.aside, scene.source) : '';
    const renamedNote = [joinedNote, sceneNote, sliceInfoReadText(sliceInfoRead), renamedText(renamed), skippedText(skipped), added].filter(Boolean).join(' ');
    if (first !== null) {
      this.sampleId = null;
      // A session's own surface first, else the one asked for (the link's, or the one last chosen).
      this.selectFile(first, this.files.get(first)?.session?.surface ?? this.surface);
      this.runOrReadFrame(first);
    }
    // Several files at once: each refusal would replace the one before in the banner (and a file
    // that opens would hide them all), so the banner names every file not opened, once, at the end.
    if (refused.length > 0 && count > 1) {
      // A biv-me folder's SliceInfoFile beside the GPFile that opened is no refusal; nor are the
      // DICOM images beside a segmentation or structure set of theirs (a PACS export's folder).
      const sliceInfo = first !== null ? refused.filter(isSliceInfoRefusal) : [];
      const images = first !== null ? refused.filter(isImageRefusal) : [];
      const aside = [...sliceInfo, ...images];
      const notOpened = refused.filter((e) => !aside.includes(e));
      const notCount = notOpened.reduce((n, e) => n + (refusedFiles.get(e) ?? 1), 0);
      const note = first === null ? '' : [
        sliceInfo.length > 0 ? setAsideText(sliceInfo.map((e) => e.file ?? 'SliceInfoFile.txt'), first) : '',
        images.length > 0 ? imagesAsideText(images.length, first, images.every(isDicomImageRefusal) ? 'DICOM image' : 'image') : '',
      ].filter(Boolean).join(' ');
      const list = notOpened.map((e) => describeError(e) + (refusedStacks.has(e) ? ` (its stack ${refusedStacks.get(e)} is not opened either)` : '')).join('; ');
      const notes = [note, renamedNote].filter(Boolean).join(' ');
      if (first === null) this.fail(refused[refused.length - 1], undefined, ` None of the ${count} files opened: ${list}.`);
      else if (notOpened.length === 0) this.parts.banner.showInfo(notes);
      else this.parts.banner.showWarning(`${notCount} of ${count - aside.length} files not opened: ${list}.${notes ? ` ${notes}` : ''} Showing ${first}.`);
    } else if (renamedNote) {
      this.parts.banner.showInfo(renamedNote);
    }
  }

  /** Opens the files under a picked folder, as a dropped folder's (io/folderDrop.ts chooses which). */
  async openFolder(picked: File[]): Promise<void> {
    const { kept, skipped } = await withSegmentations(filesOfPickedFolder(picked, undefined, this.waitsForImages), async (f) => f);
    return this.openFiles(kept, skipped);
  }

  /**
   * Opens cvi42 workspaces with the other files opened with them as their images: only a header
   * slice of each image is read (io/dicomHeaders.ts), kept by the core client for frame reloads.
   * The notes line says how many images placed contours, the warning line what was set aside;
   * `archives`: ZIP archives given with them that could not be read (named in the banner).
   */
  private async openStudy(study: Cvi42Study<File>, skipped: number, tried = false, archives: readonly CoreErrorData[] = []): Promise<boolean> {
    const { images, unreadable: lost } = await imageHeaders(study.images, pathInFolder);
    let first: string | null = null;
    const refused: CoreErrorData[] = [];
    const previous = this.currentFile()?.fileName ?? null;
    for (const workspace of study.workspaces) {
      const bytes = await this.bytesOf(workspace, refused);
      if (bytes === null) continue;
      const identity = fileIdentity(workspace);
      const name = distinctName(workspace.name, identity, this.identities);
      if (await this.loadBytes(name, bytes, identity, images)) first ??= name;
      else if (this.lastRefusal) refused.push(this.lastRefusal);
    }
    // Tried as the images of a workspace refused before: not them, they open as any files do.
    if (tried && first === null) return false;
    // Contours alone (a workspace, a Sunnybrook contours folder): the core asks for their images,
    // and the next files opened are tried as them.
    const alone = study.workspaces.length === 1 && refused.length === 1;
    if (alone && asksForImages(refused[0].message)) {
      this.waitingStudy = study;
      const unread = archives.length > 0 ? ` ${archivesText(archives)}` : '';
      this.fail(refused[0], undefined, `${keptText(previous)} Open its images next (drop them, or the folder that holds them): they are read with it.${unread}`);
    }
    const notes = [archivesText(archives), skippedText(skipped, true), lostText(lost)].filter(Boolean).join(' ');
    if (first !== null) {
      this.sampleId = null;
      this.selectFile(first, this.surface);
      this.runOrReadFrame(first);
    }
    if (refused.length > 0 && study.workspaces.length > 1) {
      const list = refused.map((e) => describeError(e)).join('; ');
      if (first === null) this.fail(refused[refused.length - 1], undefined, ` None of the ${study.workspaces.length} workspaces opened: ${list}.${notes ? ` ${notes}` : ''}`);
      else this.parts.banner.showWarning(`${refused.length} of ${study.workspaces.length} workspaces not opened: ${list}.${notes ? ` ${notes}` : ''} Showing ${first}.`);
    } else if (first !== null && archives.length > 0) {
      this.parts.banner.showWarning(notes);
    } else if (first !== null && notes) {
      this.parts.banner.showInfo(notes);
    }
    return first !== null;
  }

  /** Whether the next files opened are tried first as the images of a workspace refused without them. */
  get waitsForImages(): boolean {
    return this.waitingStudy !== null;
  }

  /**
   * Each file with, for a label map, its grid (a stack, or a single slice: a long-axis view)
   * and its bytes, in the order given. Other files are told apart by their first bytes and read
   * when they are loaded (a folder's 200 contour files are not all held at once); a lone file is
   * read here. `unreadable`: why a file could not be read.
   */
  private async readFiles(files: readonly File[]): Promise<Opened[]> {
    const out: Opened[] = [];
    for (const file of files) {
      try {
        if (files.length > 1 && !(await this.mayBeLabelMapFile(file))) {
          out.push({ file, grid: null, bytes: null });
          continue;
        }
        const bytes = await file.arrayBuffer();
        out.push({ file, grid: await this.gridOf(bytes), bytes });
      } catch (e) {
        out.push({ file, grid: null, bytes: null, unreadable: e });
      }
    }
    return out;
  }

  /**
   * Whether a file among several may be a label map, told from its first bytes; of DICOM files,
   * only segmentations (their header's SOP class): an image's pixels are never read for this.
   */
  private async mayBeLabelMapFile(file: File): Promise<boolean> {
    const head = await file.slice(0, LABEL_MAP_HEAD).arrayBuffer();
    if (!mayBeLabelMap(head)) return false;
    return !looksDicom(new Uint8Array(head)) || isSegmentationFile(file);
  }

  /** A GPFile's SliceInfoFile as the companion it is sent with (none: no file, or it could no longer be read, said). */
  private async sliceInfoOf(info: File | undefined, refused: CoreErrorData[]): Promise<ViewFile[]> {
    if (!info) return [];
    const bytes = await this.bytesOf(info, refused);
    return bytes === null ? [] : [{ name: info.name, bytes }];
  }

  /** A file's bytes read when it is loaded (null: refused, it could no longer be read). */
  private async bytesOf(file: File, refused: CoreErrorData[]): Promise<ArrayBuffer | null> {
    try {
      return await file.arrayBuffer();
    } catch (e) {
      refused.push(this.refuse(file.name, unreadable(file, e)));
      return null;
    }
  }

  /**
   * The grid of a label map (NIfTI-1 plain or gzip, NRRD, DICOM SEG), read from its header by the core; null for
   * any other file (told apart by its first bytes, without asking the core) or if the core fails.
   */
  private async gridOf(bytes: ArrayBuffer): Promise<LabelMapGrid | null> {
    const client = this.client;
    if (!client || !mayBeLabelMap(bytes)) return null;
    try {
      return await client.labelMapGrid(bytes);
    } catch {
      return null;
    }
  }

  async trySample(sample: Sample, surface: string | null = null): Promise<void> {
    this.cancelRun();
    this.waitingStudy = null; // an example opened instead of the workspace's images
    this.dispatch({ type: 'load', fileName: sample.file });
    if (!(await this.ready)) return;
    let bytes: ArrayBuffer;
    try {
      bytes = await fetchSample(sample);
    } catch (e) {
      this.fail(asCoreError(e, `could not load ${sample.file}`, sample.file));
      return;
    }
    const name = distinctName(sample.file, `sample:${sample.id}`, this.identities);
    const grid = await this.gridOf(bytes);
    if (await this.loadBytes(name, bytes, `sample:${sample.id}`, [], grid)) {
      this.sampleId = sample.id;
      this.selectFile(name, surface ?? sample.surface);
      this.runOrReadFrame(name);
    }
  }

  /**
   * Parses a file in the worker (a label-map stack with the long-axis `views` opened with it; `grid`:
   * its label-map grid, null if it is none); returns whether it worked (errors are shown).
   */
  private async loadBytes(fileName: string, bytes: ArrayBuffer, identity: string, views: ViewFile[] = [], grid: LabelMapGrid | null = null): Promise<boolean> {
    const client = this.client;
    if (!client) return false;
    this.dispatch({ type: 'load', fileName });
    this.lastRefusal = null;
    try {
      // A file that waits in the worker behind a step of seconds (a heavy input) stops that run,
      // its steps staying on screen; the client replaces the worker if the step does not end soon.
      // Read anew, a stack has the views opened with it (those of an earlier reading are forgotten).
      const loaded = await client.load(fileName, bytes, () => this.stopRun(), views);
      this.cancelRun(); // read: it replaces what was on screen
      this.files.delete(fileName); // re-insert at the end: newest last in the picker
      // Read again (dropped anew, another frame): the meshes kept of its other surfaces may be of other contours.
      if (this.kept.boundTo(`${fileName}\n`)) this.kept.forget();
      this.files.set(fileName, loaded);
      this.readings.set(fileName, (this.readings.get(fileName) ?? 0) + 1);
      this.identities.set(fileName, identity);
      if (isStack(grid)) this.stacks.add(fileName);
      else this.stacks.delete(fileName);
      // Read anew: its ids may name other contours now; a session brings the list it was saved with.
      this.leftOut.clearFile(fileName);
      if (loaded.session) this.applySession(loaded.session, loaded);
      this.emitLeaveOut();
      this.dispatch({ type: 'loaded', fileName });
      this.parts.banner.hide();
      this.pendingRunFailure = null; // that run was replaced by this file's
      return true;
    } catch (e) {
      const names = views.map((v) => v.name);
      const error = viewRefusal(asCoreError(e, 'could not read the file', fileName), names);
      // A view the core could not read: the stack read with it is not opened either.
      this.refuse(fileName, error, names.includes(error.file ?? '') ? ` ${stackNotOpened(fileName)}.` : '');
      return false;
    }
  }

  /**
   * Reads the label-map stack `stack` (loaded) again with long-axis views added to its own (a view of
   * the same name replaces the older one), as the frame it is read as; returns whether it worked.
   * A view the core cannot read leaves the stack as it was, named in the banner.
   */
  private async addViews(stack: string, views: ViewFile[]): Promise<boolean> {
    const client = this.client;
    if (!client) return false;
    this.dispatch({ type: 'load', fileName: stack });
    this.lastRefusal = null;
    try {
      const loaded = await client.addViews(stack, views, () => this.stopRun());
      this.cancelRun(); // read: it replaces what was on screen
      // Other contours: the meshes kept of its surfaces are of the stack without these views.
      if (this.kept.boundTo(`${stack}\n`)) this.kept.forget();
      this.files.set(stack, loaded);
      this.readings.set(stack, (this.readings.get(stack) ?? 0) + 1);
      this.dispatch({ type: 'loaded', fileName: stack });
      this.parts.banner.hide();
      this.pendingRunFailure = null;
      return true;
    } catch (e) {
      const names = views.map((v) => v.name);
      const error = viewRefusal(asCoreError(e, 'could not read the long-axis view', stack), names);
      const which = names.length === 1 ? 'Not added' : `None of the ${names.length} views added`;
      this.refuse(stack, error, '', ` ${which} to ${stack}; still showing it as read before.`);
      return false;
    }
  }

  /**
   * A file not opened: the previous one (if any) stays current, with its scene and framing.
   * `more`: said after what was kept; `kept`: instead of "Not opened; still showing ...".
   */
  private refuse(fileName: string, e: unknown, more = '', kept?: string): CoreErrorData {
    const previous = this.currentFile()?.fileName ?? null;
    const failed = this.pendingRunFailure;
    this.pendingRunFailure = null;
    const also = failed ? ` Meanwhile the run of ${previous ?? 'the previous file'} failed: ${describeError({ ...failed, file: undefined })}` : '';
    const error = asCoreError(e, 'could not read the file', fileName);
    this.lastRefusal = error;
    this.fail(error, undefined, (kept ?? keptText(previous)) + more + also);
    return error;
  }

  /**
   * A saved session brings the settings it was made with: they replace the current ones; the
   * contours it had left out (of any surface) are the list of `file` as read.
   */
  private applySession(session: SessionSettings, file: LoadedFile): void {
    this.leftOut.set({ file: file.fileName, frame: namedFrame(file) }, session.leave_out ?? []);
    this.params = { ...defaultParams(this.schema), ...session.params };
    this.lids = session.lids;
    this.options = withDefaultOptions(session.options);
    this.parts.params.setValues(this.params, this.lids, this.options);
    this.renderWarnings();
    this.updateUrl();
  }

  chooseFile(fileName: string): void {
    if (!this.files.has(fileName)) return;
    this.sampleId = null;
    this.selectFile(fileName, this.surface);
    this.runOrReadFrame(fileName);
  }

  /** A surface picked by the user: it runs, and any "All" still queued is dropped. */
  chooseSurface(surface: string): void {
    this.allQueue = [];
    this.pickSurface(surface);
  }

  /**
   * "All": every surface of the file in turn, the current one last, so the run ends where the user
   * was with the others kept around it (the view's Other surfaces, switched on). Picking a surface,
   * another file or frame, a parameter, Stop or a failed run drops what is still queued. The
   * biventricular epicardium is left out (unless it is the current one): it wraps the other
   * surfaces it is made of, and drawn faint around them it would veil them.
   */
  runAllSurfaces(): void {
    const file = this.currentFile();
    if (!file || file.surfaces.length < 2) return;
    const order = surfaceOrder(file.surfaces).filter((s) => s !== BIV_EPI || s === this.surface);
    const current = this.surface ?? order[0];
    this.allQueue = [...order.filter((s) => s !== current), current];
    if (!this.view.others) {
      this.parts.view.show({ ...this.view, others: true });
      this.setView({ ...this.view, others: true });
    }
    this.nextOfAll();
  }

  private nextOfAll(): void {
    const next = this.allQueue.shift();
    if (next !== undefined) this.pickSurface(next);
  }

  private pickSurface(surface: string): void {
    const file = this.currentFile();
    if (!file || !file.surfaces.includes(surface)) return;
    this.surface = surface;
    this.parts.files.setSurfaces(file.surfaces, surface);
    this.syncOthers();
    const noFrame = missingFrameNote(file, this.frame);
    this.fileWarnings = [...(noFrame ? [noFrame] : []), ...warningsFor(file, surface)];
    this.renderWarnings();
    this.runView.showContours(null);
    this.frameSurface(file);
    this.updateUrl();
    this.startRun();
  }

  /**
   * A frame picked (a `FrameOption.value`): the file is read again as that frame and runs, the
   * run in progress cancelled at once, as for a surface picked. The choice holds for files opened
   * later, as the surface does, and goes in the link.
   */
  chooseFrame(value: string): void {
    const file = this.currentFile();
    if (!file || !framePicker(file)) return;
    this.allQueue = [];
    this.frame = frameChoice(value);
    this.updateUrl();
    void this.readFrame(file.fileName, this.frame);
  }

  /** Runs the file just made current, or first reads it as the frame asked for (then runs). */
  private runOrReadFrame(fileName: string): void {
    const frame = frameToRead(this.files.get(fileName) ?? null, this.frame);
    if (frame === null) this.startRun();
    else void this.readFrame(fileName, frame);
  }

  /**
   * Reads a loaded file again as time frame `frame` (null: each contour's first) and runs it. The
   * status says "loading" meanwhile; a frame the core cannot read leaves the file as it was, named
   * in the banner. An answer overtaken by a later frame, file or sample is kept (it is what the
   * worker holds now) but not shown.
   */
  private async readFrame(fileName: string, frame: string | null): Promise<void> {
    const client = this.client;
    if (!client) return;
    const token = ++this.frameToken;
    if (this.restartTimer) clearTimeout(this.restartTimer);
    this.restartTimer = null;
    // Ended at once, as for a surface picked (the file would otherwise wait behind its steps); its
    // steps stay on screen until the frame is read, and stay there if it cannot be.
    if (this.active) {
      this.cancelRun();
      this.dispatch({ type: 'stop' });
    }
    this.dispatch({ type: 'load', fileName });
    const current = () => token === this.frameToken && this.state.kind === 'loading' && this.state.fileName === fileName;
    try {
      const loaded = await client.loadFrame(fileName, frame);
      if (this.files.has(fileName)) this.files.set(fileName, loaded);
      if (!current()) return;
      this.dispatch({ type: 'loaded', fileName });
      // The same heart in the same coordinates: the camera stays, so the phases compare on screen.
      this.selectFile(fileName, this.surface, false);
      this.startRun();
    } catch (e) {
      if (!current()) return;
      const error = asCoreError(e, `frame ${frame ?? 'first of each'} could not be read`, fileName);
      this.fail(error, undefined, ` Still showing ${fileName} as read before.`);
      this.parts.files.setFrames(framePicker(this.files.get(fileName) ?? null));
    }
  }

  /** Makes `fileName` current (state -> ready) and shows its contours (`reframe`: the camera fits them). */
  private selectFile(fileName: string, preferredSurface: string | null, reframe = true): void {
    const file = this.files.get(fileName);
    if (!file) return;
    this.allQueue = [];
    if (loadedFile(this.state) !== fileName || this.state.kind === 'loading') {
      this.dispatch({ type: 'load', fileName });
      this.dispatch({ type: 'loaded', fileName });
    }
    const s = file.surfaces;
    this.surface =
      preferredSurface && s.includes(preferredSurface) ? preferredSurface : s.includes('LV_ENDO') ? 'LV_ENDO' : (s[0] ?? null);
    this.parts.files.setFiles([...this.files.keys()], fileName);
    this.parts.files.setSurfaces(s, this.surface);
    this.parts.files.setFrames(framePicker(file));
    // Asked for a surface the file lacks (a link's ?surface=RV_ENDO, an LV-only file): say which one runs instead.
    const missing = preferredSurface && !s.includes(preferredSurface) && this.surface
      ? [`surface ${preferredSurface} is not in ${fileName}: showing ${this.surface}`]
      : [];
    const noFrame = missingFrameNote(file, this.frame);
    if (noFrame) missing.push(noFrame);
    this.fileWarnings = [...missing, ...warningsFor(file, this.surface)];
    this.renderWarnings();
    this.clearRunDisplay();
    this.runView.showContours(null);
    this.parts.viewer?.landmarkLayer.set(file.landmarks);
    this.syncOthers();
    if (reframe) this.frameSurface(file);
    this.updateUrl();
  }

  /**
   * Points the camera at the contours of the chosen surface, at their own scale: a file whose run
   * the core then refuses (a heart in metres, say) stays framed, so the user sees what was refused.
   */
  private frameSurface(file: LoadedFile): void {
    this.parts.viewer?.frame(surfacePoints(file, this.surface));
    this.frameOthers();
  }

  /**
   * With Other surfaces on, widens the framing to hold them too (the RV beside an LV would be cut
   * off at the LV's scale), keeping the orientation of the current surface's contours; a camera the
   * user moved stays where it is.
   */
  private frameOthers(): void {
    const viewer = this.parts.viewer;
    const others = this.view.others ? this.kept.others(this.surface) : [];
    if (!viewer || others.length === 0) return;
    const all = new Float32Array(others.reduce((n, m) => n + m.positions.length, 0));
    let at = 0;
    for (const m of others) {
      all.set(m.positions, at);
      at += m.positions.length;
    }
    viewer.extendFrame(all, true);
  }

  private currentFile(): LoadedFile | null {
    const name = loadedFile(this.state);
    return name ? (this.files.get(name) ?? null) : null;
  }

  // ---- hooks for the validation lab (web/src/lab) -----------------------------------------------

  /** The core client once it is up (the lab sends its own requests through it). */
  get coreClient(): CoreClient | null {
    return this.client;
  }

  /** Loads generated contour bytes (a simulated acquisition) and shows them, without a run. */
  async loadGenerated(fileName: string, bytes: ArrayBuffer): Promise<boolean> {
    this.cancelRun();
    if (!(await this.ready)) return false;
    if (!(await this.loadBytes(fileName, bytes, `generated:${fileName}`))) return false;
    this.sampleId = null;
    this.selectFile(fileName, null);
    return true;
  }

  /** What a run would use now: the current file, surface, parameters, lids and options. */
  runSettings(): { fileName: string; surface: string | null; params: ParamValues; lids: LidsMode; options: ReconOptions } | null {
    const file = this.currentFile();
    if (!file) return null;
    return {
      fileName: file.fileName,
      surface: this.surfaceOf(file),
      params: { ...this.params },
      lids: this.lids,
      options: { ...this.options },
    };
  }

  /**
   * The phases of one heart now open and the settings a Function measurement would use (null
   * with fewer than two phases); its keys change whenever the contours or the settings do.
   */
  functionContext(): FunctionContext | null {
    const plan = phasesOf(this.currentFile(), [...this.files.values()], (name) => this.identities.get(name)?.startsWith('generated:') ?? false);
    if (!plan) return null;
    // A phase that is a file is the worker's reading of it (its frame, its views, dropped anew).
    const readings = plan.kind === 'files' ? plan.phases.map((p) => [this.readings.get(p.file) ?? 0, this.files.get(p.file)?.timeFrames?.read ?? null]) : [this.readings.get(plan.phases[0].file) ?? 0];
    // Each phase leaves out what the Contours panel left out of its file and frame, so its volumes
    // are the runs' on screen.
    const applied = plan.phases.map((p) => this.leftOutOfPhase(p));
    const phases = plan.phases.map((p, i) => (applied[i].ids.length > 0 ? { ...p, leave_out: applied[i].ids } : p));
    return {
      plan: { ...plan, phases },
      params: { ...this.params },
      lids: this.lids,
      options: { ...this.options },
      phasesKey: JSON.stringify([plan.phases, readings]),
      leftOutNote: leftOutNote(applied),
      settingsKey: JSON.stringify([schemaOrdered(this.params, this.schema), this.lids, Object.entries(this.options).sort(([a], [b]) => a.localeCompare(b)), phases.map((p) => p.leave_out ?? [])]),
    };
  }

  /**
   * The list of phase `p`'s file and frame, as far as its contours are known: an id its contours
   * lack would fail every cell of the phase (the core's `unknown_contour`), while the CLI's
   * `volumes` leaves each phase the ids it has. The app knows the contours of each file's reading
   * on screen; a list of another frame of a sequence was made while that frame was read, of its
   * contours.
   */
  private leftOutOfPhase(p: PhaseSpec): { file: string; frame: string | null; ids: string[] } {
    const file = this.files.get(p.file) ?? null;
    const reading = namedFrame(file);
    const frame = p.frame !== undefined ? p.frame : reading;
    const ids = this.leftOut.listsOf(p.file).filter((l) => sameReading(l.key.frame, frame)).flatMap((l) => l.ids);
    const known = file && sameReading(reading, frame) ? new Set(file.contours.map((c) => c.id)) : null;
    return { file: p.file, frame, ids: [...new Set(ids)].filter((id) => known === null || known.has(id)) };
  }

  /** Called whenever `functionContext` may have changed (files, frames, parameters). */
  onContextChange(listener: () => void): void {
    this.contextListeners.push(listener);
  }

  /** Called with each finished run's result, and with null whenever the shown result is cleared. */
  onResult(listener: (r: RunResult | null) => void): void {
    this.resultListeners.push(listener);
  }

  private emitResult(r: RunResult | null): void {
    for (const l of this.resultListeners) callSafely(() => l(r), 'result listener failed');
  }

  // ---- contours left out by the user (the Contours panel) -------------------------------------

  /** The key of the current file and frame's list (null: no file). */
  private leaveOutKey(): LeaveOutKey | null {
    const file = this.currentFile();
    return file ? { file: file.fileName, frame: namedFrame(file) } : null;
  }

  /**
   * The ids the user left out of the current file and frame, whatever their surface: what the
   * next run of any of its surfaces leaves out, as the CLI's `--leave-out` ([] without a file).
   */
  leaveOutNow(): string[] {
    const key = this.leaveOutKey();
    return key ? this.leftOut.get(key) : [];
  }

  /** The surface a run of `file` would be of (null: the file's one unnamed surface). */
  private surfaceOf(file: LoadedFile): string | null {
    return file.surfaces.length ? this.surface : null;
  }

  /** The current surface's contours (the Contours panel's rows) in file order: id and the core's SAX/LAX split at load. */
  private surfaceContours(file: LoadedFile): { id: string; kind: ContourKindName | null }[] {
    const surface = this.surfaceOf(file);
    return file.contours.filter((c) => partOf(c.surface, surface)).map((c) => ({ id: c.id, kind: c.kind }));
  }

  /**
   * What the Contours panel is about: the current file, frame and surface as one key (its rows
   * are of one surface), the ids of its contours left out and its contours (null without a file).
   */
  contourContext(): { key: string; leaveOut: string[]; fileContours: { id: string; kind: ContourKindName | null }[] } | null {
    const file = this.currentFile();
    const key = this.leaveOutKey();
    if (!file || !key) return null;
    const fileContours = this.surfaceContours(file);
    const mine = new Set(fileContours.map((c) => c.id));
    return { key: JSON.stringify({ ...key, surface: this.surfaceOf(file) }), leaveOut: this.leftOut.get(key).filter((id) => mine.has(id)), fileContours };
  }

  /**
   * Leaves contour `id` out of the current file and frame (`out`) or puts it back, then runs again
   * as a parameter change does (debounced, the run in progress cancelled; an "All" still queued
   * dropped). Every surface's next run leaves it out.
   */
  setLeftOut(id: string, out: boolean): void {
    const key = this.leaveOutKey();
    if (!key || !this.leftOut.toggle(key, id, out)) return;
    this.leaveOutChanged();
  }

  /**
   * Puts back, in one run, every contour left out but those of the file's other surfaces: the
   * Contours panel's rows are the current surface's, and an id no contour of this reading has
   * (a session's) is no other surface's choice to keep.
   */
  useAllContours(): void {
    const file = this.currentFile();
    const key = this.leaveOutKey();
    if (!file || !key) return;
    const mine = new Set(this.surfaceContours(file).map((c) => c.id));
    const others = new Set(file.contours.map((c) => c.id).filter((id) => !mine.has(id)));
    const back = this.leftOut.get(key).filter((id) => !others.has(id));
    if (this.leftOut.putBack(key, back)) this.leaveOutChanged();
  }

  private leaveOutChanged(): void {
    this.allQueue = [];
    this.emitLeaveOut();
    this.syncWall();
    for (const l of this.contextListeners) callSafely(l, 'context listener failed');
    if (this.restartTimer) clearTimeout(this.restartTimer);
    this.restartTimer = setTimeout(() => this.startRun(), RESTART_DEBOUNCE_MS);
  }

  /** Called whenever a leave-out list may have changed (a box ticked, Use all, a file or session read). */
  onLeaveOutChange(listener: () => void): void {
    this.leaveOutListeners.push(listener);
  }

  private emitLeaveOut(): void {
    for (const l of this.leaveOutListeners) callSafely(l, 'leave-out listener failed');
  }

  // ---- runs -----------------------------------------------------------------------------------

  /** (Re)starts the reconstruction of the current file with the current parameters. */
  startRun(): void {
    if (this.restartTimer) clearTimeout(this.restartTimer);
    this.restartTimer = null;
    const client = this.client;
    const settings = this.runSettings();
    if (!client || !settings || this.state.kind === 'loading') return;
    this.cancelRun();
    this.clearRunDisplay();
    if (this.runNote) {
      this.runNote = null;
      this.renderWarnings();
    }
    this.parts.result.clear('running…');
    const leaveOut = this.leaveOutNow();
    const handle = client.run(leaveOut.length > 0 ? { ...settings, leaveOut } : settings, (f) => this.onFrame(f));
    this.active = { runId: handle.runId, cancel: () => handle.cancel(), settings: this.settingsKeyOf(settings) };
    this.dispatch({ type: 'run', runId: handle.runId });
    handle.done.then(
      (r) => this.onDone(r),
      (e) => {
        if (this.active?.runId !== handle.runId) return; // cancelled or replaced: not an error
        this.active = null;
        this.parts.result.clear('no result (see the error)');
        this.runFailed(asCoreError(e, 'the reconstruction failed', settings.fileName), handle.runId);
      },
    );
  }

  private cancelRun(): void {
    const a = this.active;
    this.active = null;
    a?.cancel();
  }

  /**
   * Stop: ends the computation in progress (and a restart still waiting for its debounce). The
   * steps it recorded stay on screen to scrub through; there is no result; ↻ runs again.
   */
  stopRun(): void {
    if (this.restartTimer) clearTimeout(this.restartTimer);
    this.restartTimer = null;
    if (!this.active || !canStop(this.state)) return;
    this.allQueue = [];
    this.cancelRun();
    this.parts.result.clear('stopped before the end: no result (↻ runs again)');
    this.dispatch({ type: 'stop' });
  }

  /**
   * The warning line of the current file; with Keep specks and strays on, the core's lines about
   * contours left out end with a note that they are used (as the CLI's `--keep-specks` note); a
   * line about second loops, with a note on the option that leaves them out.
   */
  private renderWarnings(): void {
    const warnings = [...this.fileWarnings];
    for (const note of [keptSpecksNote(warnings, this.options.keep_specks), secondLoopsNote(warnings, this.options.drop_second_loops)]) {
      if (note) warnings.push(note);
    }
    if (this.runNote) warnings.push(this.runNote);
    this.parts.warnings.textContent = warnings.length ? `⚠ ${warnings.join(' · ')}` : '';
    this.parts.warnings.hidden = warnings.length === 0;
    // The reader's account of the file (a label map's labels, its long-axis views): information.
    this.parts.notes.show(this.currentFile()?.notes ?? []);
  }

  /** A parameter changed: debounce, then restart (cancelling the run in progress). */
  setParams(values: ParamValues, lids: LidsMode, options: ReconOptions = this.options): void {
    this.allQueue = [];
    this.params = { ...this.params, ...values };
    this.lids = lids;
    this.options = { ...options };
    this.renderWarnings();
    this.updateUrl();
    this.syncWall();
    if (this.restartTimer) clearTimeout(this.restartTimer);
    this.restartTimer = setTimeout(() => this.startRun(), RESTART_DEBOUNCE_MS);
  }

  resetParams(): void {
    this.params = defaultParams(this.schema);
    this.lids = 'auto';
    this.options = { ...DEFAULT_OPTIONS };
    this.parts.params.setValues(this.params, this.lids, this.options);
    this.setParams(this.params, this.lids, this.options);
  }

  private onFrame(f: Frame): void {
    if (!this.active || f.runId !== this.active.runId) return;
    if (f.growthNote) {
      this.runNote = f.growthNote;
      this.renderWarnings();
    }
    this.runView.frame(f);
  }

  private onDone(r: RunResult): void {
    if (!this.active || r.runId !== this.active.runId) return;
    const settings = this.active.settings;
    this.active = null;
    this.runView.finished(r);
    this.parts.status.setProgress(1);
    this.parts.result.show(r);
    // A run finished: whatever error was shown has been dealt with (not a file refused meanwhile,
    // nor the files of a drop that were not opened: hideError keeps a warning).
    if (this.state.kind !== 'error') this.parts.banner.hideError();
    this.parts.exports.setAvailable(true, true);
    this.keepSurface(r, settings);
    this.dispatch({ type: 'finished', runId: r.runId });
    this.emitResult(r);
    if (this.allQueue.length) this.nextOfAll();
  }

  /**
   * A finished run's mesh joins the file's other surfaces (shown faint while another is current),
   * with the settings it was run with (`settings`) and its vertices in full precision (the LV wall).
   */
  private keepSurface(r: RunResult, settings: string): void {
    this.syncOthers();
    if (r.surface === null) return;
    this.kept.keep(r.surface, r.positions, r.indices, settings, r.positionsF64, r.leave_out ?? []);
    this.parts.viewer?.otherSurfacesLayer.set(r.surface, r.positions, r.indices, runSignature(r));
    this.syncOthers();
  }

  /**
   * Keeps the kept surfaces to the file and frame on screen (another one: forget them) and shows
   * them but the current surface, whose own run is on screen; the export offers them all.
   */
  private syncOthers(): void {
    const file = this.currentFile();
    const layer = this.parts.viewer?.otherSurfacesLayer;
    if (this.kept.bind(file ? `${file.fileName}\n${this.frame ?? ''}` : null)) layer?.clear();
    const others = this.kept.others(this.surface).map((m) => m.surface);
    layer?.show(this.view.others, this.surface);
    this.parts.view.setOthersAvailable(others);
    this.parts.exports.setOthers(others);
    this.syncWall();
    this.parts.viewer?.requestRender();
  }

  /**
   * What a run of any surface would be run with now (the settings in the panel, or `s`, and the
   * file and frame's whole leave-out list), as kept meshes record theirs: a changed list leaves
   * every surface's kept run stale, as a changed parameter does.
   */
  private settingsKeyOf(s?: { params: ParamValues; lids: LidsMode; options: ReconOptions }): string {
    const { params, lids, options } = s ?? { params: this.params, lids: this.lids, options: this.options };
    return settingsKey(params, lids, options) + leaveOutKeyPart(this.leaveOutNow());
  }

  /**
   * Whether the LV wall can be built now: the current file's LV_ENDO and LV_EPI both have a kept
   * mesh run with the settings in the panel (export/wall.ts).
   */
  wallReadiness(): WallReadiness {
    const file = this.currentFile();
    return wallReadiness(file ? file.surfaces : null, (s) => this.kept.get(s), this.settingsKeyOf());
  }

  /**
   * Whether the biventricular wall can be built now: the current file's LV_ENDO, RV_ENDO and
   * BIV_EPI (the core's join of its LV_EPI and RV_EPI curves) all have a kept mesh run with the
   * settings in the panel (export/bivWall.ts).
   */
  bivWallReadiness(): BivWallReadiness {
    const file = this.currentFile();
    return bivWallReadiness(file ? file.surfaces : null, (s) => this.kept.get(s), this.settingsKeyOf());
  }

  /**
   * Tells the export panel whether the LV and biventricular walls can be built now (the file, its
   * runs or the settings changed), and which finished run the anatomical mesh is of.
   */
  private syncWall(): void {
    this.parts.exports.setWall(this.wallReadiness());
    this.parts.exports.setBivWall(this.bivWallReadiness());
    this.parts.exports.setAnatomical(this.anatomicalKey());
  }

  /** The finished run on screen, as the anatomical mesh's row tells runs apart (null: none). */
  private anatomicalKey(): string | null {
    const file = this.currentFile();
    const r = this.runView.currentResult;
    return file && r ? JSON.stringify([file.fileName, namedFrame(file), r.runId, r.surface]) : null;
  }

  /**
   * The finished run on screen resampled onto the anatomical `layout` in the worker, from its
   * mesh in full precision (where the core gave it) and the settings it was run with (its base
   * plane is cut of the contours it followed), written as `format`, with the app's header lines
   * when `header`; null without a finished run. The core refuses a surface or file that can have
   * none, saying why.
   */
  anatomicalFile(layout: AnatomicalLayout, format: AnatomicalFormat, header: boolean): Promise<{ summary: AnatomicalSummary; bytes: Uint8Array }> | null {
    const r = this.runView.currentResult;
    const info = this.exportInfo();
    if (!r || !info || !this.client) return null;
    const leaveOut = r.leave_out ?? [];
    return this.client.anatomicalFile(
      { fileName: info.fileName, surface: r.surface, params: r.params, lids: r.lids, options: r.options, leaveOut },
      {
        mesh: { surface: r.surface ?? '', positions: r.positionsF64 ?? Float64Array.from(r.positions), indices: r.indices },
        rings: layout.rings,
        points: layout.points,
        format,
        header: header ? anatomicalHeaderLines(info) : [],
      },
    );
  }

  /** Draws an anatomical mesh the Export panel built as PLY over the surface; throws when it cannot be read or there is no 3D view. */
  showAnatomical(built: BuiltAnatomical): void {
    const viewer = this.parts.viewer;
    if (!viewer) throw new Error('there is no 3D view (WebGL is disabled in this browser)');
    const grid = wallSolidFromPly(built.bytes);
    viewer.showGrid(grid.positions, grid.indices);
  }

  /** Takes the anatomical mesh out of the 3D view. */
  hideAnatomical(): void {
    this.parts.viewer?.hideGrid();
  }

  /**
   * The LV wall of the current file built in the worker from its kept LV_ENDO and LV_EPI meshes
   * (full precision where the core gave it), written as `format`; null when it cannot be built now.
   */
  wallFile(format: WallFormat): Promise<{ summary: WallSummary; bytes: Uint8Array }> | null {
    const src = this.wallSources();
    if (!src || !this.client) return null;
    return this.client.wallFile(src.settings, {
      endo: src.endo,
      epi: src.epi,
      minThicknessMm: WALL_MIN_THICKNESS_MM,
      format,
      header: wallHeaderLines(src.now, src.endo.surface, src.epi.surface, WALL_MIN_THICKNESS_MM),
    });
  }

  /**
   * What a file built of the LV wall's two surfaces needs (the wall, its hexahedra): the kept
   * LV_ENDO and LV_EPI meshes (full precision where the core gave it), the run settings with the
   * file and frame's leave-out list, and the export info for the header; null when the LV wall
   * cannot be built now.
   */
  private wallSources() {
    const w = this.wallReadiness();
    const settings = this.runSettings();
    const info = this.exportInfo();
    if (!w.ready || !settings || !info) return null;
    const mesh = (m: KeptMesh) => ({ surface: m.surface, positions: m.positions64 ?? Float64Array.from(m.positions), indices: m.indices });
    // Both meshes were run with the file and frame's list (readiness checks it): the base plane
    // is cut of the contours they follow.
    const leaveOut = this.leaveOutNow();
    const now = { ...info, params: schemaOrdered(this.params, this.schema), lids: this.lids, options: this.options, leaveOut };
    return { settings: { ...settings, leaveOut }, endo: mesh(w.endo as KeptMesh), epi: mesh(w.epi as KeptMesh), now };
  }

  /**
   * The LV wall of the current file as layers of hexahedra of `layout`, built in the worker from
   * the kept LV_ENDO and LV_EPI meshes the LV wall is made of (full precision where the core gave
   * them), with the app's header lines when `header`; null when the LV wall cannot be built now.
   * The core refuses a file that does not say where the septum is, saying why.
   */
  hexFile(layout: HexLayout, header: boolean): Promise<BuiltHex> | null {
    const src = this.wallSources();
    if (!src || !this.client) return null;
    return this.client.hexFile(src.settings, {
      endo: src.endo,
      epi: src.epi,
      rings: layout.rings,
      points: layout.points,
      layers: layout.layers,
      header: header ? hexHeaderLines(src.now, src.endo.surface, src.epi.surface) : [],
    });
  }

  /**
   * The biventricular wall of the current file built in the worker from its kept LV_ENDO, RV_ENDO
   * and BIV_EPI meshes (full precision where the core gave it), written as `format`; null when it
   * cannot be built now.
   */
  bivWallFile(format: WallFormat): Promise<{ summary: WallSummary; bytes: Uint8Array }> | null {
    const w = this.bivWallReadiness();
    const settings = this.runSettings();
    const info = this.exportInfo();
    if (!w.ready || !settings || !info || !this.client) return null;
    const mesh = (m: KeptMesh) => ({ surface: m.surface, positions: m.positions64 ?? Float64Array.from(m.positions), indices: m.indices });
    const leaveOut = this.leaveOutNow();
    const now = { ...info, params: schemaOrdered(this.params, this.schema), lids: this.lids, options: this.options, leaveOut };
    return this.client.bivWallFile({ ...settings, leaveOut }, {
      lvEndo: mesh(w.lvEndo as KeptMesh),
      rvEndo: mesh(w.rvEndo as KeptMesh),
      bivEpi: mesh(w.bivEpi as KeptMesh),
      minThicknessMm: WALL_MIN_THICKNESS_MM,
      format,
      header: bivWallHeaderLines(now, w.lvEndo.surface, w.bivEpi.surface, w.rvEndo.surface, WALL_MIN_THICKNESS_MM),
    });
  }

  /** The finished meshes of the file's surfaces but the current one (for the all-surfaces export). */
  otherSurfaceMeshes(): KeptMesh[] {
    return this.kept.others(this.surface);
  }

  private clearRunDisplay(): void {
    // A new run, another file or surface: a wall shown from the Export panel makes way for it.
    this.parts.exports.hideWall();
    this.runView.clear();
    this.emitResult(null);
  }

  /**
   * Shows a wall the Export panel built as PLY (`id`: its row) in the 3D view in place of the
   * surface, coloured as the view panel says; throws when its bytes cannot be read or there is no
   * 3D view (the row then says so, and the surface stays).
   */
  showWall(id: string, wall: BuiltWall): void {
    const viewer = this.parts.viewer;
    if (!viewer) throw new Error('there is no 3D view (WebGL is disabled in this browser)');
    viewer.showWall(wallSolidFromPly(wall.bytes), this.view.wallColour, id);
    this.parts.view.setWallShown(true, this.view.wallColour);
  }

  /** Takes the wall out of the 3D view: the reconstruction is drawn again. */
  hideWall(): void {
    this.parts.viewer?.hideWall();
    this.parts.view.setWallShown(false, this.view.wallColour);
  }

  /** The view panel's Wall colour: by thickness or by region (the wall shown, and the next one; in the link). */
  setWallColouring(colouring: WallColouring): void {
    this.view = { ...this.view, wallColour: colouring };
    this.parts.viewer?.setWallColouring(colouring);
    this.updateUrl();
  }

  // ---- timeline -------------------------------------------------------------------------------

  togglePlay(): void {
    this.dispatch({ type: this.runView.togglePlay() ? 'resume' : 'pause' });
    // Pausing the replay of a finished run changes no state (done stays done): the button must
    // still say so (it kept showing "Pause" over a paused replay).
    this.runView.updateTimeline();
  }

  step(delta: number): void {
    this.runView.step(delta);
    this.dispatch({ type: 'pause' });
  }

  seek(index: number): void {
    this.runView.seek(index);
    this.dispatch({ type: 'pause' });
  }

  first(): void {
    this.seek(0);
  }

  latestStep(): void {
    this.runView.toLatest();
    this.dispatch({ type: 'resume' });
  }

  setSpeed(speed: Speed): void {
    this.runView.setSpeed(speed);
  }

  // ---- view -----------------------------------------------------------------------------------

  setView(v: ViewSettings): void {
    const othersOn = v.others && !this.view.others;
    this.view = v;
    this.applyView();
    if (othersOn) this.frameOthers();
    this.updateUrl();
  }

  resetView(): void {
    this.parts.viewer?.resetView();
  }

  private applyView(): void {
    const viewer = this.parts.viewer;
    if (!viewer) return;
    viewer.meshLayer.setWireframe(this.view.wireframe);
    viewer.meshLayer.setOpacity(this.view.opacity);
    viewer.wallLayer.setWireframe(this.view.wireframe);
    viewer.wallLayer.setOpacity(this.view.opacity);
    viewer.attractorLayer.setVisible(this.view.attractors);
    viewer.landmarkLayer.setVisible(this.view.landmarks);
    viewer.givenLayer.setVisible(this.view.asGiven);
    this.syncOthers();
    viewer.setClip(this.view.clip);
    viewer.requestRender();
  }

  onHover(info: Parameters<HoverReadout['show']>[0]): void {
    this.parts.hover.show(info, this.runView.colourMax(info?.what === 'mesh' ? 'mesh' : 'points'));
  }

  screenshot(): Promise<Blob> {
    const viewer = this.parts.viewer;
    return viewer ? viewer.screenshot() : Promise.reject(new Error('no 3D view'));
  }

  exportInfo(): ExportInfo | null {
    const file = this.currentFile();
    if (!file) return null;
    const r = this.runView.currentResult;
    return {
      appVersion: this.appVersion,
      coreVersion: r?.version ?? this.coreVersion,
      fileName: file.fileName,
      surface: r ? r.surface : this.surface,
      frame: namedFrame(file),
      lids: r ? r.lids : this.lids,
      options: r?.options ?? this.options,
      params: schemaOrdered(r ? r.params : this.params, this.schema),
      // What the run on screen left out at the user's request (before its result: what the next run will).
      leaveOut: r?.leave_out ?? this.leaveOutNow(),
      coordinateSystem: file.coordinateSystem ?? null,
    };
  }

  /**
   * The current file as a heartmesh session (its contours with the settings now in the panel:
   * parameters, mesh ends, options, surface, and every surface's contours left out), to open
   * again later; null without a file.
   */
  sessionFile(): Promise<Uint8Array> | null {
    const settings = this.runSettings();
    if (!settings || !this.client) return null;
    const leaveOut = this.leaveOutNow();
    return this.client.sessionFile(leaveOut.length > 0 ? { ...settings, leaveOut } : settings, this.appVersion);
  }

  /** An export that failed (a bad setting, say): the banner says why; the state does not change. */
  showExportError(e: unknown): void {
    this.parts.banner.showError(asCoreError(e, 'the export failed', this.currentFile()?.fileName));
  }

  currentResult(): RunResult | null {
    return this.runView.currentResult;
  }

  /** The current file as loaded (its points as given), for the e2e tests and the console. */
  currentFileData(): LoadedFile | null {
    return this.currentFile();
  }

  // ---- state ----------------------------------------------------------------------------------

  private dispatch(e: AppEvent): void {
    const next = transition(this.state, e);
    if (next === this.state) return;
    this.state = next;
    this.setStatus();
  }

  /**
   * The live run failed. A file being read meanwhile (the run goes on until it is) decides what
   * the banner says: a refused file's message then carries this failure too, a file that reads
   * replaces the run. With a refusal showing, the failure becomes the error (status line and
   * banner agree) and the refusal stays as a note.
   */
  private runFailed(error: CoreErrorData, runId: number): void {
    this.allQueue = [];
    const s = this.state;
    if (s.kind === 'loading') {
      this.pendingRunFailure = error;
      return;
    }
    if (s.kind === 'error') {
      const refused = s.error.file && s.error.file !== error.file ? ' (not opened)' : '';
      this.fail(error, runId, ` Earlier: ${describeError(s.error)}${refused}.`);
      return;
    }
    this.fail(error, runId);
  }

  private fail(error: CoreErrorData, runId?: number, context = ''): void {
    this.dispatch({ type: 'failed', error, runId });
    if (this.state.kind === 'error') this.parts.banner.showError(error, context);
  }

  private setStatus(): void {
    const s = this.state;
    const starting = !this.coreUp && s.kind === 'empty';
    this.parts.status.setStatus(starting ? 'starting the core…' : statusWord(s), starting ? 'starting' : s.kind, currentRunId(s));
    this.parts.viewer?.setAnimating(isComputing(s));
    this.parts.timeline.setRunControls(canStop(s), this.currentFile() !== null && s.kind !== 'loading');
    document.body.dataset.state = s.kind;
    document.body.dataset.hasFile = this.currentFile() ? '1' : '0';
    this.runView.updateTimeline();
    this.parts.exports.setAvailable(this.runView.currentResult !== null, this.currentFile() !== null);
    this.syncWall();
  }

  /** The link holds the settings and the file's frame: whatever changes it may change the Function context too. */
  private updateUrl(): void {
    for (const l of this.contextListeners) callSafely(l, 'context listener failed');
    if (this.schema.length === 0) return;
    const query = serializeUrlState(
      { params: this.params, lids: this.lids, options: this.options, surface: this.surface, frame: this.frame, sample: this.sampleId, view: this.view },
      this.schema,
    );
    const url = `${location.pathname}${query}${location.hash}`;
    if (url !== `${location.pathname}${location.search}${location.hash}`) history.replaceState(null, '', url);
  }

  /** For tests and the console. */
  get debug(): { state: AppState; historyLength: number; runId: number | null } {
    return { state: this.state, historyLength: this.runView.historyLength, runId: this.active?.runId ?? currentRunId(this.state) };
  }

  dispose(): void {
    this.runView.stopLoop();
    this.cancelRun();
    this.client?.dispose();
    this.parts.viewer?.dispose();
  }
}

export { asCoreError } from './errors';
