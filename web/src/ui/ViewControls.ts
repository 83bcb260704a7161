/**
 * View toggles over the viewport: wireframe, attractors, landmarks, the contours as given (only
 * meaningful after a run with breath-hold alignment: disabled otherwise), the file's other
 * surfaces (disabled until another surface of the file has been run), opacity, clipping plane,
 * reset view; while a myocardium wall is shown (the Export panel's View), what colours it:
 * thickness or region.
 */
import type { ViewSettings } from '../app/urlState';
import type { WallColouring } from '../viewer/wallColours';
import { h } from './dom';

const AS_GIVEN_ON = 'The file\'s contours before the breath-hold shifts, faint and dashed: the mesh follows the shifted ones';
const AS_GIVEN_OFF = 'Contours as given: shown after a run with "Align breath-holds" on';
const OTHERS_OFF = 'Other surfaces of the file (LV, RV, epicardium), faint around this one: each appears once its own run has finished (pick it in the Surface menu)';

/** The one-column layout of styles.css (a phone, a tablet held upright). */
const NARROW = '(max-width: 859px)';

export class ViewControls {
  readonly element: HTMLElement;
  private readonly wire: HTMLInputElement;
  private readonly attractors: HTMLInputElement;
  private readonly landmarks: HTMLInputElement;
  private readonly asGiven: HTMLInputElement;
  private readonly asGivenLabel: HTMLElement;
  private readonly others: HTMLInputElement;
  private readonly othersLabel: HTMLElement;
  private readonly othersCount: HTMLElement;
  private readonly opacity: HTMLInputElement;
  private readonly clip: HTMLInputElement;
  private readonly opacityOut: HTMLOutputElement;
  private readonly clipOut: HTMLOutputElement;
  /** Wall colour (thickness | region), shown only while a wall is. */
  private readonly wallColour: HTMLSelectElement;
  private readonly wallColourRow: HTMLElement;

  constructor(onChange: (v: ViewSettings) => void, onResetView: () => void, onWallColour: (c: WallColouring) => void = () => undefined) {
    this.wire = h('input', { type: 'checkbox', id: 'view-wire', 'data-testid': 'view-wireframe' });
    this.attractors = h('input', { type: 'checkbox', id: 'view-attr', 'data-testid': 'view-attractors' });
    this.landmarks = h('input', { type: 'checkbox', id: 'view-landmarks', 'data-testid': 'view-landmarks' });
    this.asGiven = h('input', { type: 'checkbox', id: 'view-as-given', 'data-testid': 'view-as-given', disabled: true });
    this.others = h('input', { type: 'checkbox', id: 'view-others', 'data-testid': 'view-others', disabled: true });
    this.opacity = h('input', { type: 'range', id: 'view-opacity', min: 5, max: 100, step: 1, 'data-testid': 'view-opacity' });
    this.clip = h('input', { type: 'range', id: 'view-clip', min: 0, max: 100, step: 1, 'data-testid': 'view-clip' });
    this.opacityOut = h('output', { for: 'view-opacity' });
    this.clipOut = h('output', { for: 'view-clip' });
    this.wallColour = h(
      'select',
      { id: 'view-wall-colour', 'data-testid': 'wall-colour' },
      h('option', { value: 'thickness' }, 'by thickness'),
      h('option', { value: 'region' }, 'by region'),
    );
    this.wallColour.addEventListener('change', () => onWallColour(this.wallColour.value === 'region' ? 'region' : 'thickness'));
    this.wallColourRow = h(
      'label',
      { class: 'select-row', for: 'view-wall-colour', hidden: true, title: 'Colour the wall by its thickness (mm) or by region (epicardium, endocardia, base)' },
      'Wall',
      this.wallColour,
    );
    const reset = h('button', { type: 'button', class: 'small', 'data-testid': 'reset-view', title: 'Reset view (R)' }, 'Reset view');
    reset.addEventListener('click', onResetView);
    const emit = () => {
      const v = this.read();
      this.show(v);
      onChange(v);
    };
    for (const el of [this.wire, this.attractors, this.landmarks, this.asGiven, this.others]) el.addEventListener('change', emit);
    this.asGivenLabel = h(
      'label',
      { class: 'check', title: AS_GIVEN_OFF },
      this.asGiven, h('span', { class: 'swatch given' }), 'Contours as given',
    );
    this.othersCount = h('span', { class: 'muted', 'data-testid': 'view-others-count' });
    this.othersLabel = h('label', { class: 'check disabled', title: OTHERS_OFF }, this.others, 'Other surfaces', this.othersCount);
    for (const el of [this.opacity, this.clip]) el.addEventListener('input', emit);
    // A <details>: open on a wide screen (its summary hidden), folded to a "View" button on a
    // phone, where the open panel would cover a third of the heart in the view.
    const details = h(
      'details',
      { class: 'view-controls', role: 'group', 'aria-label': 'View', open: true },
      h('summary', { class: 'view-summary', title: 'View settings: wireframe, attractors, landmarks, opacity, clipping' }, 'View'),
      h(
        'div',
        { class: 'view-controls-body' },
        h('label', { class: 'check' }, this.wire, 'Wireframe'),
        h('label', { class: 'check' }, this.attractors, h('span', { class: 'swatch attr' }), 'Attractors'),
        h('label', { class: 'check', title: 'Valves, apex and other landmark points of the file' }, this.landmarks, h('span', { class: 'swatch lmk' }), 'Landmarks'),
        this.asGivenLabel,
        this.othersLabel,
        h('label', { class: 'range', for: 'view-opacity' }, 'Opacity', this.opacity, this.opacityOut),
        h('label', { class: 'range', for: 'view-clip', title: 'Cut away the near part of the mesh to look inside' }, 'Clip', this.clip, this.clipOut),
        this.wallColourRow,
        reset,
      ),
    );
    this.element = details;
    const narrow = typeof matchMedia === 'function' ? matchMedia(NARROW) : null;
    if (narrow) {
      details.open = !narrow.matches;
      narrow.addEventListener?.('change', (e) => (details.open = !e.matches));
    }
  }

  private read(): ViewSettings {
    return {
      wireframe: this.wire.checked,
      attractors: this.attractors.checked,
      landmarks: this.landmarks.checked,
      asGiven: this.asGiven.checked,
      others: this.others.checked,
      opacity: Number(this.opacity.value) / 100,
      clip: Number(this.clip.value) / 100,
      wallColour: this.wallColour.value === 'region' ? 'region' : 'thickness',
    };
  }

  /** Whether the shown result was aligned (the toggle does something only then). */
  setAsGivenAvailable(on: boolean): void {
    this.asGiven.disabled = !on;
    this.asGivenLabel.classList.toggle('disabled', !on);
    this.asGivenLabel.title = on ? AS_GIVEN_ON : AS_GIVEN_OFF;
  }

  /** The file's other surfaces that have a finished run to show (the toggle does something only then). */
  setOthersAvailable(surfaces: readonly string[]): void {
    const on = surfaces.length > 0;
    this.others.disabled = !on;
    this.othersLabel.classList.toggle('disabled', !on);
    this.othersLabel.title = on ? `Faint around this surface: ${surfaces.join(', ')} as their last runs left them` : OTHERS_OFF;
    this.othersCount.textContent = on ? ` (${surfaces.length})` : '';
  }

  /** Whether a wall is shown (the Wall colour menu is there only then), and its colouring. */
  setWallShown(on: boolean, colouring: WallColouring): void {
    this.wallColourRow.hidden = !on;
    this.wallColour.value = colouring;
  }

  show(v: ViewSettings): void {
    this.wire.checked = v.wireframe;
    this.attractors.checked = v.attractors;
    this.landmarks.checked = v.landmarks;
    this.asGiven.checked = v.asGiven;
    this.others.checked = v.others;
    this.opacity.value = String(Math.round(v.opacity * 100));
    this.clip.value = String(Math.round(v.clip * 100));
    this.wallColour.value = v.wallColour;
    this.opacityOut.textContent = `${Math.round(v.opacity * 100)} %`;
    this.clipOut.textContent = v.clip >= 1 ? 'off' : `${Math.round(v.clip * 100)} %`;
  }
}
