// Types of saxOnly.mjs for the TypeScript tests.
export const SAX_ONLY_NAME: string;
export const APEX_Z: number;
export function saxOnlyEllipsoid(options?: { a?: number; b?: number; c?: number; points?: number }): { csv: string; heights: number[] };
