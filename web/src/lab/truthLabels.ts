/**
 * Surface labels of the Lab's truths (pure, unit-tested): several truths are several surfaces of
 * one heart sliced on one acquisition, and each label becomes the `surface` column of the
 * simulated file, so a reconstruction of LV_ENDO is compared with the LV_ENDO truth and never
 * with another. The rule for a label is the CLI's (`heartmesh simulate LABEL=FILE`, and the core
 * checks it again); the guess from a file name saves typing for the usual names
 * (`bivme-patient1-ED-RV_ENDO-closed.obj`, `cardiomesh-spasm-LV_epi.obj`).
 */

/** The surfaces the app knows by name, in the picker's order. */
export const KNOWN_LABELS = ['LV_ENDO', 'LV_EPI', 'RV_ENDO', 'RV_EPI', 'BIV_EPI'] as const;

/** A known surface name inside a file name: LV/RV/BIV, an optional `_` or `-`, ENDO/EPI (any case). */
const IN_NAME = /(?:^|[^a-z0-9])(lv|rv|biv)[_-]?(endo|epi)(?:cardium)?(?=$|[^a-z0-9])/i;

/** The label a mesh file's name suggests (null: none recognisable, to be asked for). */
export function guessLabel(fileName: string): string | null {
  const base = fileName.replace(/^.*[\\/]/, '').replace(/\.[^.]+$/, '');
  const m = IN_NAME.exec(base);
  if (!m) return null;
  const label = `${m[1]}_${m[2]}`.toUpperCase();
  return (KNOWN_LABELS as readonly string[]).includes(label) ? label : null;
}

/** What the readers take as a surface label: letters, digits, `_` and `-`, 1 to 64 of them. */
export function isLabel(s: string): boolean {
  return s.length > 0 && s.length <= 64 && /^[A-Za-z0-9_-]+$/.test(s);
}

/**
 * Why `label` cannot be truth `index`'s among `labels` (the truths' labels, in order): not a
 * label, or another truth's (without case, as the CLI); null when it can.
 */
export function labelProblem(label: string, index: number, labels: readonly (string | null)[]): string | null {
  if (!isLabel(label)) return `“${label}” is no surface label: letters, digits, _ and - only (e.g. LV_ENDO, RV_ENDO)`;
  const other = labels.findIndex((l, k) => k !== index && l !== null && l.toUpperCase() === label.toUpperCase());
  return other >= 0 ? `the label ${label} is already truth ${other + 1}'s: give each truth its own` : null;
}

/**
 * Labels for mesh files joining the truths whose labels are `existing`: each file's guess unless
 * another truth (held or joining before it) has it; `clash` names the label it could not take.
 */
export function labelsForNew(names: readonly string[], existing: readonly (string | null)[]): { label: string | null; clash: string | null }[] {
  const taken = new Set(existing.filter((l): l is string => l !== null).map((l) => l.toUpperCase()));
  return names.map((name) => {
    const guess = guessLabel(name);
    if (guess === null) return { label: null, clash: null };
    if (taken.has(guess)) return { label: null, clash: guess };
    taken.add(guess);
    return { label: guess, clash: null };
  });
}

/** Why these truths cannot be simulated together (several need a label each); null: they can. */
export function simulateProblem(truths: readonly { name: string; label: string | null }[]): string | null {
  if (truths.length < 2) return null;
  const unlabelled = truths.filter((t) => t.label === null).map((t) => t.name);
  if (unlabelled.length === 0) return null;
  return `give each truth a surface label (LV_ENDO, RV_ENDO, …): ${unlabelled.join(', ')} ${unlabelled.length > 1 ? 'have' : 'has'} none`;
}

/**
 * The truth a reconstruction of `surface` is measured against, as the core picks it: the only one,
 * else the one of the same label (without case); null when there is none.
 */
export function truthForSurface(surface: string | null, labels: readonly (string | null)[]): number | null {
  if (labels.length === 1) return 0;
  if (surface === null) return null;
  const k = labels.findIndex((l) => l !== null && l.toUpperCase() === surface.toUpperCase());
  return k >= 0 ? k : null;
}
