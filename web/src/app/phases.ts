/**
 * Which phases of one heart the Function panel measures, from what is open: the time frames of
 * the file on screen when it holds a sequence (the Frame picker's: a cine GPFile, a CSV with a
 * frame or phase column, a 4D label map), else every open file, one phase each (the ED and ES
 * files). Named as the CLI's `heartmesh volumes` names them, so the CSVs agree: a file by its name
 * without the extension, a frame by its label as the file writes it. Pure, so the rules are
 * unit-tested.
 */
import type { LoadedFile, PhaseSpec } from '../core-client/protocol';
import { splitExtension } from '../io/fileExtension';
import { framePicker } from './timeFrames';

export interface PhasePlan {
  /** `frames`: of one file holding a sequence; `files`: one open file each. */
  kind: 'frames' | 'files';
  phases: PhaseSpec[];
  /** What the phases are, for the panel's caption ("the frames of cine.csv", "the 2 open files"). */
  source: string;
}

/**
 * The phases to measure, or null with fewer than two (no function to measure). `simulated` marks
 * the Lab's simulated acquisitions (`lab-parametric-LV-8sax-2lax.csv`): a phantom, not a phase of
 * the heart whose files are open, so never one of the phases.
 */
export function phasesOf(current: LoadedFile | null, allOpen: readonly LoadedFile[], simulated: (fileName: string) => boolean = () => false): PhasePlan | null {
  const open = allOpen.filter((f) => !simulated(f.fileName));
  const picker = framePicker(current);
  if (current && picker) {
    const frames = current.timeFrames?.frames ?? [];
    return {
      kind: 'frames',
      phases: frames.map((f) => ({ name: f, file: current.fileName, frame: f })),
      source: `the ${frames.length} frames of ${current.fileName}`,
    };
  }
  if (open.length < 2) return null;
  const stems = open.map((f) => splitExtension(f.fileName)[0] || f.fileName);
  return {
    kind: 'files',
    // Two files of one stem (a.csv, a.txt) keep their whole names apart.
    phases: open.map((f, i) => ({ name: stems.filter((s) => s === stems[i]).length > 1 ? f.fileName : stems[i], file: f.fileName })),
    source: `the ${open.length} open files`,
  };
}
