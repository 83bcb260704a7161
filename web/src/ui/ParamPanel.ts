/**
 * The parameter panel, generated from the core's schema (ParamSpec[] from CoreClient.schema()), so
 * a parameter added in Rust appears here without UI changes. Log-scale parameters (lambda) get a
 * log slider. Below them, the modes that are not numbers: mesh ends (lids), the smoothing method
 * the softening of conflicting attractors, the breath-hold alignment,
 * the closing of open ends with its apex floor for short-axis-only stacks, the keeping of
 * specks and strays, and the leaving out of second loops. Emits every change; the controller debounces and restarts the run.
 */
import { DEFAULT_OPTIONS, SMOOTHING_METHODS, type LidsMode, type ParamSpec, type ParamValues, type ReconOptions } from '../core-client/protocol';
import { h } from './dom';
import { formatValue, sliderSteps, sliderToValue, valueToSlider } from './sliderScale';

/** Short labels for the schema names (the help text from the schema is the tooltip). */
const LABELS: Record<string, string> = {
  iterations: 'Iterations',
  lambda: 'λ (lambda)',
  beta: 'β (beta)',
  attractors: 'Attractor count',
  attractor_spacing: 'Attractor spacing',
  resample_attractors_every: 'Re-sample attractors every',
  remesh_every: 'Remesh every',
  smoothing_iterations: 'Smoothing iterations',
  smoothing_factor: 'Smoothing factor',
  target_reduction: 'Decimation target reduction',
  ring_points: 'Initial ring points',
};

/** One line under each option, like the sliders' schema help. */
const SMOOTHING_HELP =
  'how each remesh smooths: the paper\'s umbrella smoothing with an affine correction (default), Taubin λ/μ (factor at most 0.6), ' +
  'or umbrella smoothing with a local correction instead of the affine one: HC, or twicing (factor at most 0.5); see docs/VALIDATION.md, session 11';
const SOFTEN_HELP = 'in the final steps, down-weight short- and long-axis attractors that disagree instead of letting the surface fold';
const ALIGN_HELP =
  'before reconstructing, shift each short-axis slice and long-axis view in its own plane (a slice also along the long axis, where the views show it) so the curves meet where the planes cross; ' +
  'use it when slices were acquired in separate breath-holds and the stack looks staggered (the mesh then follows the shifted contours)';

const END_CAPS_HELP =
  'where no contour closes an end of the cavity (the base of most files; both ends of an RV without a long-axis curve), ' +
  'add down-weighted lid points there so the mesh stops at the data instead of running on past it and inflating the volume; ' +
  'turn it off when the anatomy really continues past the last slice, or to compare with the paper\'s method';

const APEX_FLOOR_HELP =
  'for short-axis-only stacks (no long-axis curve reaches the apex): one lid point at the tip the most apical rings\' taper predicts ' +
  'pulls the mesh down while it stops short of it, instead of leaving the apex to the extrapolation, which stops short of it; ' +
  'the result panel\'s "Closed ends" says "apex floor" when one was placed; a file with a long-axis curve at the apex is unaffected; ' +
  'on by default, works with Close open ends; turn it off for the paper\'s extrapolation';

const KEEP_SPECKS_HELP =
  'use every contour, also the ones the reconstruction otherwise leaves out (drawn grey and dashed, named in the warning): ' +
  'a stray, further from the rest of its surface than the span of all the others (another series, a wrong coordinate), ' +
  'and a speck, a short-axis ring under a tenth of the ring one slice away, not at the apex (a slice grazing the rim past the base, a stray click); ' +
  'tick it when such a contour is real anatomy (the paper\'s method keeps every contour)';

const DROP_SECOND_LOOPS_HELP =
  'leave out a closed loop lying apart (over 3 mm) from the main loop of its short-axis slice (an outflow tract, another structure drawn under the same label), ' +
  'named in the warning, so the surface follows each slice\'s main loop instead of being pulled out towards it in a spike; ' +
  'off by default (the paper\'s method uses every contour): tick it when the other loop is not part of this cavity';

/** The options that are one checkbox each: the key in ReconOptions, the test id stem, the label and the help. */
type CheckKey = 'soften_conflicts' | 'align_slices' | 'apex_floor' | 'keep_specks' | 'drop_second_loops';
const CHECKS: readonly { key: CheckKey; id: string; label: string; help: string }[] = [
  { key: 'soften_conflicts', id: 'soften-conflicts', label: 'Soften conflicting SAX/LAX attractors', help: SOFTEN_HELP },
  { key: 'align_slices', id: 'align-slices', label: 'Align breath-holds', help: ALIGN_HELP },
  { key: 'apex_floor', id: 'apex-floor', label: 'Apex floor (short-axis-only stacks)', help: APEX_FLOOR_HELP },
  { key: 'keep_specks', id: 'keep-specks', label: 'Keep specks and strays', help: KEEP_SPECKS_HELP },
  { key: 'drop_second_loops', id: 'drop-second-loops', label: 'Leave out second loops', help: DROP_SECOND_LOOPS_HELP },
];

/** Text shown instead of 0 for parameters where 0 means "automatic". */
const ZERO_MEANS: Record<string, string> = { attractors: 'auto', attractor_spacing: 'off' };

interface Row {
  spec: ParamSpec;
  slider: HTMLInputElement;
  output: HTMLOutputElement;
}

export class ParamPanel {
  readonly element: HTMLElement;
  private rows = new Map<string, Row>();
  private readonly list: HTMLElement;
  private readonly lids: HTMLSelectElement;
  private values: ParamValues = {};
  private lidsMode: LidsMode = 'auto';
  private readonly smoothing: HTMLSelectElement;
  private readonly endCaps: HTMLInputElement;
  /** The one-checkbox options, by their key in ReconOptions. */
  private readonly checks = new Map<CheckKey, HTMLInputElement>();
  private options: ReconOptions = { ...DEFAULT_OPTIONS };

  constructor(
    private readonly onChange: (values: ParamValues, lids: LidsMode, options: ReconOptions) => void,
    onReset: () => void,
  ) {
    this.list = h('div', { class: 'param-list' });
    this.lids = h(
      'select',
      { id: 'param-lids', 'data-testid': 'param-lids' },
      h('option', { value: 'auto' }, 'closed (lids from long axis)'),
      h('option', { value: 'none' }, 'open (no lids)'),
    );
    this.lids.addEventListener('change', () => {
      this.lidsMode = this.lids.value === 'none' ? 'none' : 'auto';
      this.emit();
    });
    this.smoothing = h(
      'select',
      { id: 'param-smoothing-method', 'data-testid': 'param-smoothing-method', 'aria-describedby': 'param-smoothing-method-help' },
      h('option', { value: 'laplacian-affine' }, 'Laplacian + affine correction'),
      h('option', { value: 'taubin' }, 'Taubin (λ/μ)'),
      h('option', { value: 'laplacian-hc' }, 'Laplacian + local correction (HC)'),
      h('option', { value: 'laplacian-twicing' }, 'Laplacian + twicing'),
    );
    this.smoothing.addEventListener('change', () => {
      const method = SMOOTHING_METHODS.find((m) => m === this.smoothing.value) ?? DEFAULT_OPTIONS.smoothing_method;
      this.options = { ...this.options, smoothing_method: method };
      this.renderOptions();
      this.emit();
    });
    for (const c of CHECKS) {
      const box = h('input', {
        type: 'checkbox', id: `param-${c.id}`, 'data-testid': `param-${c.id}`, 'aria-describedby': `param-${c.id}-help`,
      });
      box.addEventListener('change', () => {
        this.options = { ...this.options, [c.key]: box.checked };
        this.renderOptions();
        this.emit();
      });
      this.checks.set(c.key, box);
    }
    this.endCaps = h('input', {
      type: 'checkbox', id: 'param-end-caps', 'data-testid': 'param-end-caps',
      'aria-describedby': 'param-end-caps-help',
    });
    this.endCaps.addEventListener('change', () => {
      this.options = { ...this.options, end_caps: this.endCaps.checked ? 'auto' : 'off' };
      this.renderOptions();
      this.emit();
    });
    const reset = h('button', { type: 'button', class: 'small', 'data-testid': 'reset-params', title: 'All parameters back to the defaults of the method' }, 'Reset to defaults');
    reset.addEventListener('click', onReset);
    this.element = h(
      'section',
      { class: 'panel params', 'aria-label': 'Parameters' },
      h('h2', {}, 'Parameters'),
      this.list,
      h('div', { class: 'param-row' }, h('label', { for: 'param-lids' }, 'Mesh ends'), this.lids),
      h(
        'div',
        { class: 'param-row param-option', title: SMOOTHING_HELP },
        h('label', { for: 'param-smoothing-method' }, 'Smoothing'),
        this.smoothing,
        h('div', { class: 'param-help', id: 'param-smoothing-method-help' }, SMOOTHING_HELP),
      ),
      this.checkRow('soften_conflicts'),
      this.checkRow('align_slices'),
      h(
        'div',
        { class: 'param-row param-option', title: END_CAPS_HELP },
        h('label', { class: 'param-check', for: 'param-end-caps' }, this.endCaps, 'Close open ends'),
        h('div', { class: 'param-help', id: 'param-end-caps-help' }, END_CAPS_HELP),
      ),
      this.checkRow('apex_floor'),
      this.checkRow('keep_specks'),
      this.checkRow('drop_second_loops'),
      h('div', { class: 'panel-actions' }, reset),
    );
  }

  /** Builds the rows from the schema (once the core answered). */
  setSchema(schema: readonly ParamSpec[]): void {
    this.list.replaceChildren();
    this.rows.clear();
    for (const spec of schema) {
      const id = `param-${spec.name}`;
      const slider = h('input', {
        type: 'range', id, min: 0, max: sliderSteps(spec), step: 1,
        'data-testid': id, 'data-param': spec.name, 'aria-describedby': `${id}-help`,
      });
      const output = h('output', { for: id, class: 'param-value' });
      const label = h('label', { for: id, title: spec.help }, LABELS[spec.name] ?? spec.name.replace(/_/g, ' '));
      const help = h('div', { class: 'param-help', id: `${id}-help` }, spec.help);
      const row = h('div', { class: 'param-row', title: spec.help }, h('div', { class: 'param-head' }, label, output), slider, help);
      slider.addEventListener('input', () => {
        const v = sliderToValue(spec, Number(slider.value));
        this.values[spec.name] = v;
        output.textContent = this.format(spec, v);
        output.classList.toggle('changed', v !== spec.default);
        this.emit();
      });
      this.rows.set(spec.name, { spec, slider, output });
      this.list.append(row);
    }
    this.render();
  }

  /** Shows values without emitting a change. */
  setValues(values: ParamValues, lids: LidsMode, options: ReconOptions): void {
    this.values = { ...values };
    this.lidsMode = lids;
    this.options = { ...options };
    this.render();
  }

  /** Ticks Align breath-holds (if it is not already) and starts the run, as a click on it would. */
  alignBreathHolds(): void {
    if (this.options.align_slices) return;
    this.options = { ...this.options, align_slices: true };
    this.renderOptions();
    this.emit();
  }

  private emit(): void {
    this.onChange({ ...this.values }, this.lidsMode, { ...this.options });
  }

  /** The options' controls, marked like a changed slider when not at the core's default. */
  private renderOptions(): void {
    this.smoothing.value = this.options.smoothing_method;
    this.smoothing.classList.toggle('changed', this.options.smoothing_method !== DEFAULT_OPTIONS.smoothing_method);
    for (const [key, box] of this.checks) {
      box.checked = this.options[key];
      box.parentElement?.classList.toggle('changed', this.options[key] !== DEFAULT_OPTIONS[key]);
    }
    this.endCaps.checked = this.options.end_caps === 'auto';
    this.endCaps.parentElement?.classList.toggle('changed', this.options.end_caps !== DEFAULT_OPTIONS.end_caps);
    // The floor is one of the lid points: without Close open ends it has nothing to act through.
    const apexFloor = this.checks.get('apex_floor');
    if (apexFloor) {
      apexFloor.disabled = this.options.end_caps === 'off';
      apexFloor.parentElement?.classList.toggle('disabled', apexFloor.disabled);
    }
  }

  /** The row of a one-checkbox option: the box in its label, the help line under it. */
  private checkRow(key: CheckKey): HTMLElement {
    const c = CHECKS.find((x) => x.key === key);
    const box = this.checks.get(key);
    if (!c || !box) throw new Error(`no checkbox option ${key}`);
    return h(
      'div',
      { class: 'param-row param-option', title: c.help },
      h('label', { class: 'param-check', for: `param-${c.id}` }, box, c.label),
      h('div', { class: 'param-help', id: `param-${c.id}-help` }, c.help),
    );
  }

  private format(spec: ParamSpec, v: number): string {
    return v === 0 && ZERO_MEANS[spec.name] ? ZERO_MEANS[spec.name] : formatValue(spec, v);
  }

  private render(): void {
    for (const { spec, slider, output } of this.rows.values()) {
      const v = this.values[spec.name] ?? spec.default;
      slider.value = String(valueToSlider(spec, v));
      output.textContent = this.format(spec, v);
      output.classList.toggle('changed', v !== spec.default);
    }
    this.lids.value = this.lidsMode;
    this.renderOptions();
  }
}
