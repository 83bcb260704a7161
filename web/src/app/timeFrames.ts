/**
 * The Frame picker's content and the frame named beside a file, from a loaded file's time frames
 * (`LoadedFile.timeFrames`, the core's `contours::TimeFrames`). Pure, so the rules are unit-tested.
 *
 * The picker is for a sequence: a file where some contour has points in several frames (a cine
 * exported whole). A file whose slices each carry their own frame number (biv-me's example labels
 * one slice `1.0` in a frame-0 file) holds one phase of the heart and gets no picker.
 *
 * Every frame the file lists can be chosen, numbers (`9`) and text (`ED`, `ES`) alike: the core
 * reads a frame by its label (`io::FrameChoice`), comparing numbers as numbers and text trimmed
 * and in any case; `sameFrame` compares the same way, so a link's `frame=es` finds `ES`.
 */
import type { LoadedFile, TimeFrames } from '../core-client/protocol';

export interface FrameOption {
  /** The frame as the file writes it (`FIRST_OF_EACH` for the file's own reading). */
  value: string;
  label: string;
  /** Entries that are no frame to read (the count of frames not listed). */
  disabled: boolean;
  title?: string;
}

export interface FramePicker {
  options: FrameOption[];
  /** The option of the frames read. */
  value: string;
}

/** The value of "each contour's first frame": the core's reading when no frame is asked for. */
export const FIRST_OF_EACH = '';

function framesOf(file: LoadedFile | null): TimeFrames | null {
  return file?.timeFrames ?? null;
}

/** Labels longer than this are no frame (a hand-edited link); the core lists frames as written. */
export const MAX_FRAME_LABEL = 200;

/**
 * The frame a picker value or a link's `frame=` asks the core for: the label trimmed (null: each
 * contour's first, for `FIRST_OF_EACH`, blank or overlong text).
 */
export function frameChoice(value: string | null): string | null {
  const v = value?.trim() ?? '';
  return v === '' || v.length > MAX_FRAME_LABEL ? null : v;
}

/** A number as Rust's `f64` parse takes it (no hex, no blank, no `Infinity`). */
const NUMBER = /^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$/;

/** What frame labels compare by, as the core's `frame_key`: finite numbers by value, text trimmed in lower case. */
function frameKey(label: string): string {
  const v = label.trim();
  const n = NUMBER.test(v) ? Number(v) : NaN;
  return Number.isFinite(n) ? `number ${n}` : `text ${v.toLowerCase()}`;
}

/** Whether two labels name the same frame (`9` and `9.0`, `ES` and `es`). */
export function sameFrame(a: string, b: string): boolean {
  return frameKey(a) === frameKey(b);
}

function list(frames: readonly string[]): string {
  return frames.length > 3 ? `${frames.slice(0, 3).join(', ')}, …` : frames.join(', ');
}

/** The picker for `file`, or null when it holds no sequence of frames to choose from. */
export function framePicker(file: LoadedFile | null): FramePicker | null {
  const t = framesOf(file);
  if (!t || !t.sequence || t.frames.length < 2) return null;
  // The phases the file names (a Segment study's EDT and EST) beside their frames, short as the
  // top bar's picker is narrow; the option's tooltip spells them out.
  const phase = (f: string) => (f === t.endDiastole ? ['ED', 'end-diastole'] : f === t.endSystole ? ['ES', 'end-systole'] : null);
  const options: FrameOption[] = t.frames.map((f) => {
    const p = phase(f);
    return p
      ? { value: f, label: `frame ${f} · ${p[0]}`, disabled: false, title: `the file's ${p[1]}` }
      : { value: f, label: `frame ${f}`, disabled: false };
  });
  // Contours that start in different frames: the file's own reading is no one frame, and only
  // this option brings it back once a frame was chosen.
  const mixed = t.firsts.length > 1;
  if (mixed) {
    options.unshift({
      value: FIRST_OF_EACH,
      label: `first of each (${list(t.firsts)})`,
      disabled: false,
      title: "each contour's first frame, as the file is read when none is chosen",
    });
  }
  if (t.count > t.frames.length) {
    options.push({ value: '…', label: `… ${t.count - t.frames.length} more`, disabled: true, title: 'frames past the first 1000 are not listed' });
  }
  // The option of the frame read (the core names it as the file writes it, as listed).
  const read = t.chosen || !mixed ? t.read[0] : undefined;
  const value = read === undefined ? FIRST_OF_EACH : (t.frames.find((f) => sameFrame(f, read)) ?? read);
  return { options, value };
}

/**
 * The frame to name beside the file (export headers, Parameters JSON, file names): the one frame
 * read of a sequence, or one asked for (a session of one frame); null for a file of one frame.
 */
export function namedFrame(file: LoadedFile | null): string | null {
  const t = framesOf(file);
  if (!t || !(t.sequence || t.chosen) || t.read.length !== 1) return null;
  return t.read[0];
}

/**
 * The frame to read `file` as when it becomes current and `wanted` was chosen before (with the
 * picker, or by the link): null when the file is no sequence, lacks that frame, or holds it as
 * asked for already.
 */
export function frameToRead(file: LoadedFile | null, wanted: string | null): string | null {
  const t = framesOf(file);
  if (wanted === null || !t || !t.sequence) return null;
  const listed = t.frames.find((f) => sameFrame(f, wanted));
  if (listed === undefined) return null;
  return t.chosen && t.read.length === 1 && sameFrame(t.read[0], wanted) ? null : listed;
}

/** The note for a sequence that lacks the frame asked for (null otherwise). */
export function missingFrameNote(file: LoadedFile | null, wanted: string | null): string | null {
  const t = framesOf(file);
  const picker = framePicker(file);
  if (!file || !t || !picker || wanted === null || t.frames.some((f) => sameFrame(f, wanted)) || t.count > t.frames.length) return null;
  const shown = picker.options.find((o) => o.value === picker.value)?.label ?? "each contour's first frame";
  return `frame ${wanted} is not in ${file.fileName}: showing ${shown}`;
}
