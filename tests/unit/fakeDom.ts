// A minimal stand-in for the few DOM calls the plain-DOM panels make (web/src/ui/dom.ts `h`,
// dataset, replaceChildren, hidden, classList), so their rendering can be unit-tested in Node.
// Not a DOM: just enough to read back the text and attributes a panel produced.

export class FakeElement {
  readonly children: (FakeElement | string)[] = [];
  readonly attributes = new Map<string, string>();
  readonly dataset: Record<string, string> = {};
  /** Inline styles (the legends' colour bar and tick positions). */
  readonly style: Record<string, string> = {};
  hidden = false;
  title = '';
  /** The element this one was last appended to (what a panel reaches through `parentElement`). */
  parentElement: FakeElement | null = null;
  private readonly classes = new Set<string>();
  readonly classList = {
    toggle: (c: string, on?: boolean) => {
      const want = on ?? !this.classes.has(c);
      if (want) this.classes.add(c);
      else this.classes.delete(c);
      return want;
    },
    contains: (c: string) => this.classes.has(c),
  };
  constructor(readonly tagName: string) {}
  setAttribute(k: string, v: string): void {
    this.attributes.set(k, v);
    if (k.startsWith('data-')) this.dataset[camel(k.slice(5))] = v;
    if (k === 'hidden') this.hidden = true;
    if (k === 'title') this.title = v;
  }
  removeAttribute(k: string): void {
    this.attributes.delete(k);
    if (k.startsWith('data-')) delete this.dataset[camel(k.slice(5))];
  }
  getAttribute(k: string): string | null {
    return this.attributes.get(k) ?? null;
  }
  append(...nodes: (FakeElement | string)[]): void {
    this.children.push(...nodes);
    this.adopt(nodes);
  }
  replaceChildren(...nodes: (FakeElement | string)[]): void {
    this.children.length = 0;
    this.children.push(...nodes);
    this.adopt(nodes);
  }
  private adopt(nodes: (FakeElement | string)[]): void {
    for (const n of nodes) if (typeof n !== 'string') n.parentElement = this;
  }
  private readonly listeners = new Map<string, (() => void)[]>();
  addEventListener(type: string, fn: () => void): void {
    this.listeners.set(type, [...(this.listeners.get(type) ?? []), fn]);
  }
  /** Calls the listeners of `type` (a user's click or change). */
  fire(type: string): void {
    for (const fn of this.listeners.get(type) ?? []) fn();
  }
  get textContent(): string {
    return this.children.map((c) => (typeof c === 'string' ? c : c.textContent)).join('');
  }
  set textContent(v: string) {
    this.replaceChildren(v);
  }
  /** Every descendant (depth first) matching `pred`. */
  findAll(pred: (e: FakeElement) => boolean): FakeElement[] {
    const out: FakeElement[] = [];
    for (const c of this.children) {
      if (typeof c === 'string') continue;
      if (pred(c)) out.push(c);
      out.push(...c.findAll(pred));
    }
    return out;
  }
  byTestId(id: string): FakeElement | undefined {
    return this.findAll((e) => e.dataset.testid === id)[0];
  }
}

function camel(s: string): string {
  return s.replace(/-([a-z])/g, (_, c: string) => c.toUpperCase());
}

/** Installs the fake `document` (call vi.unstubAllGlobals() after). */
export const fakeDocument = {
  createElement: (tag: string) => new FakeElement(tag),
  /** SVG elements (the Lab's charts) are plain fake elements too. */
  createElementNS: (_ns: string, tag: string) => new FakeElement(tag),
};

/** The label -> value rows of the first `<dl>` under `el` (the result panel's layout). */
export function dlRows(el: FakeElement): Record<string, string> {
  const out: Record<string, string> = {};
  const cells = el.findAll((e) => e.tagName === 'dl')[0].children as FakeElement[];
  for (let i = 0; i + 1 < cells.length; i += 2) out[cells[i].textContent] = cells[i + 1].textContent;
  return out;
}
