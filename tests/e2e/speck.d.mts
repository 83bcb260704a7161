// Types of speck.mjs for the TypeScript tests.
export function withSpeck(
  csv: string,
  options?: { surface?: string; idPart?: string; id?: string; aroundMm?: number },
): { csv: string; id: string; line: number; aroundMm: number };
