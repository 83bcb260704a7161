// Types of twoFrames.mjs for the TypeScript tests.
export const TWO_FRAMES_NAME: string;
export const FRAMES: string[];
export function twoFrameGpFile(ed: string, es: string): string;
export const PHASES_NAME: string;
export const PHASES: string[];
export function phasesCsv(ed: string, es: string): string;
