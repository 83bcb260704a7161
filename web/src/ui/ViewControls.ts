/** View toggles over the viewport: wireframe, attractors, landmarks, opacity, clipping plane, reset view. */
import type { ViewSettings } from '../app/urlState';
import { h } from './dom';

export class ViewControls {
  readonly element: HTMLElement;
  private readonly wire: HTMLInputElement;
  private readonly attractors: HTMLInputElement;
  private readonly landmarks: HTMLInputElement;
  private readonly opacity: HTMLInputElement;
  private readonly clip: HTMLInputElement;
  private readonly opacityOut: HTMLOutputElement;
  private readonly clipOut: HTMLOutputElement;

  constructor(onChange: (v: ViewSettings) => void, onResetView: () => void) {
    this.wire = h('input', { type: 'checkbox', id: 'view-wire', 'data-testid': 'view-wireframe' });
    this.attractors = h('input', { type: 'checkbox', id: 'view-attr', 'data-testid': 'view-attractors' });
    this.landmarks = h('input', { type: 'checkbox', id: 'view-landmarks', 'data-testid': 'view-landmarks' });
    this.opacity = h('input', { type: 'range', id: 'view-opacity', min: 5, max: 100, step: 1, 'data-testid': 'view-opacity' });
    this.clip = h('input', { type: 'range', id: 'view-clip', min: 0, max: 100, step: 1, 'data-testid': 'view-clip' });
    this.opacityOut = h('output', { for: 'view-opacity' });
    this.clipOut = h('output', { for: 'view-clip' });
    const reset = h('button', { type: 'button', class: 'small', 'data-testid': 'reset-view', title: 'Reset view (R)' }, 'Reset view');
    reset.addEventListener('click', onResetView);
    const emit = () => {
      const v = this.read();
      this.show(v);
      onChange(v);
    };
    for (const el of [this.wire, this.attractors, this.landmarks]) el.addEventListener('change', emit);
    for (const el of [this.opacity, this.clip]) el.addEventListener('input', emit);
    this.element = h(
      'div',
      { class: 'view-controls', role: 'group', 'aria-label': 'View' },
      h('label', { class: 'check' }, this.wire, 'Wireframe'),
      h('label', { class: 'check' }, this.attractors, h('span', { class: 'swatch attr' }), 'Attractors'),
      h('label', { class: 'check', title: 'Valves, apex and other landmark points of the file' }, this.landmarks, h('span', { class: 'swatch lmk' }), 'Landmarks'),
      h('label', { class: 'range', for: 'view-opacity' }, 'Opacity', this.opacity, this.opacityOut),
      h('label', { class: 'range', for: 'view-clip', title: 'Cut away the near part of the mesh to look inside' }, 'Clip', this.clip, this.clipOut),
      reset,
    );
  }

  private read(): ViewSettings {
    return {
      wireframe: this.wire.checked,
      attractors: this.attractors.checked,
      landmarks: this.landmarks.checked,
      opacity: Number(this.opacity.value) / 100,
      clip: Number(this.clip.value) / 100,
    };
  }

  show(v: ViewSettings): void {
    this.wire.checked = v.wireframe;
    this.attractors.checked = v.attractors;
    this.landmarks.checked = v.landmarks;
    this.opacity.value = String(Math.round(v.opacity * 100));
    this.clip.value = String(Math.round(v.clip * 100));
    this.opacityOut.textContent = `${Math.round(v.opacity * 100)} %`;
    this.clipOut.textContent = v.clip >= 1 ? 'off' : `${Math.round(v.clip * 100)} %`;
  }
}
