/**
 * What the export rows that ask the core for a derived file (the anatomical mesh, the hexahedra)
 * share: whether the core will build one for this file, asked once with the smallest request,
 * and the figures line's message states. Kept here so both rows grey, wait and report alike.
 */
import { toCoreErrorData, type CoreErrorData } from '../core-client/protocolErrors';

/** A row's standing: nothing to build from, asking the core, ready, or refused with its reason. */
export type Availability = { state: 'none' } | { state: 'checking' } | { state: 'ready' } | { state: 'refused'; reason: string };

/**
 * The standing the core's answer to a probe gives: ready when it built, refused (with the
 * sentence `reason` makes of its message) when `isRefusal` says the failure is the core's own
 * refusal; any other failure (a worker restarted meanwhile) leaves the row ready, so Save tries.
 */
export async function probed(pending: Promise<unknown>, isRefusal: (e: CoreErrorData) => boolean, reason: (message: string) => string): Promise<Availability> {
  try {
    await pending;
  } catch (e) {
    const error = toCoreErrorData(e);
    if (isRefusal(error)) return { state: 'refused', reason: reason(error.message) };
  }
  return { state: 'ready' };
}

/**
 * Shows nothing (`null`) or a message (busy or an error) on a figures line, clearing the
 * `dataKeys` a built file's figures set; returns false when `content` is figures, for the row to
 * fill in.
 */
export function showMessage(el: HTMLElement, dataKeys: readonly string[], content: { state: 'busy' | 'error'; text: string } | null | object): boolean {
  el.classList.toggle('warn', false);
  for (const k of dataKeys) delete el.dataset[k];
  if (content === null) {
    el.hidden = true;
    el.textContent = '';
    el.title = '';
    delete el.dataset.state;
    return true;
  }
  el.hidden = false;
  if ('state' in content && 'text' in content) {
    el.dataset.state = content.state;
    el.textContent = content.text;
    el.title = '';
    el.classList.toggle('warn', content.state === 'error');
    return true;
  }
  return false;
}
