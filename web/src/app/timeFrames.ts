/**
 * The Frame picker's content and the frame named beside a file, from a loaded file's time frames
 * (`LoadedFile.timeFrames`, the core's `contours::TimeFrames`). Pure, so the rules are unit-tested.
 *
 * The picker is for a sequence: a file where some contour has points in several frames (a cine
 * exported whole). A file whose slices each carry their own frame number (biv-me's example labels
 * one slice `1.0` in a frame-0 file) holds one phase of the heart and gets no picker.
 */
import type { LoadedFile, TimeFrames } from '../core-client/protocol';

export interface FrameOption {
  /** The frame as the file writes it (`FIRST_OF_EACH` for the file's own reading). */
  value: string;
  label: string;
  /** Frames the core cannot be asked for (text such as `ED`, negative or fractional numbers). */
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

/** The frame number the core reads a picker value as (null: each contour's first). */
export function frameNumber(value: string): number | null {
  return /^\d+$/.test(value) && Number(value) <= 0xffffffff ? Number(value) : null;
}

function list(frames: readonly string[]): string {
  return frames.length > 3 ? `${frames.slice(0, 3).join(', ')}, …` : frames.join(', ');
}

/** The picker for `file`, or null when it holds no sequence of frames to choose from. */
export function framePicker(file: LoadedFile | null): FramePicker | null {
  const t = framesOf(file);
  if (!t || !t.sequence || t.frames.length < 2) return null;
  const options: FrameOption[] = t.frames.map((f) =>
    frameNumber(f) === null
      ? { value: f, label: `frame ${f}`, disabled: true, title: 'only frames numbered 0, 1, 2, … can be chosen' }
      : { value: f, label: `frame ${f}`, disabled: false },
  );
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
  const value = t.chosen || !mixed ? (t.read[0] ?? FIRST_OF_EACH) : FIRST_OF_EACH;
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
export function frameToRead(file: LoadedFile | null, wanted: number | null): number | null {
  const t = framesOf(file);
  if (wanted === null || !t || !t.sequence) return null;
  const w = String(wanted);
  if (!t.frames.includes(w)) return null;
  return t.chosen && t.read.length === 1 && t.read[0] === w ? null : wanted;
}

/** The note for a sequence that lacks the frame asked for (null otherwise). */
export function missingFrameNote(file: LoadedFile | null, wanted: number | null): string | null {
  const t = framesOf(file);
  const picker = framePicker(file);
  if (!file || !t || !picker || wanted === null || t.frames.includes(String(wanted)) || t.count > t.frames.length) return null;
  const shown = picker.options.find((o) => o.value === picker.value)?.label ?? "each contour's first frame";
  return `frame ${wanted} is not in ${file.fileName}: showing ${shown}`;
}
