// The explanation as a tree that folds, stepped through with Next and
// Back in the lab's order, its lines and the drawn rays linked both ways:
// hovering one highlights the other. The lines, their steps, sections and
// rays are the core's (`tracer_explain_view`); this only lays them out.

// What each of the lab's sections is about, for a line's tooltip.
const SECTIONS = {
  "1.2.3": "lab 1.2.3: the primary ray",
  "1.3": "lab 1.3: intersections",
  "1.4": "lab 1.4: lights, shadow rays",
  "1.5": "lab 1.5: mirror and glass rays",
  gamma: "the pixel: saturation and gamma",
  path: "the path, one sample",
};

// Lays `lines` out in `panel` as a folding tree: a line with deeper lines
// after it holds them, open. Each line's text ends in a newline, so the
// panel's text is the text of `tracer explain`.
export function showTree(panel, lines) {
  panel.replaceChildren();
  const stack = [{ depth: -1, box: panel }];
  lines.forEach((line, i) => {
    while (stack[stack.length - 1].depth >= line.depth) stack.pop();
    const parent = stack[stack.length - 1].box;
    const row = document.createElement("div");
    row.className = "line";
    row.dataset.index = i;
    row.dataset.step = line.step;
    if (line.section) {
      row.dataset.section = line.section;
      row.title = SECTIONS[line.section] || "";
    }
    if (line.ray !== null && line.ray !== undefined) row.dataset.ray = line.ray;
    row.textContent = `${line.text}\n`;
    const next = lines[i + 1];
    if (next && next.depth > line.depth) {
      const fold = document.createElement("details");
      fold.open = true;
      const summary = document.createElement("summary");
      summary.appendChild(row);
      fold.appendChild(summary);
      const box = document.createElement("div");
      box.className = "children";
      fold.appendChild(box);
      parent.appendChild(fold);
      stack.push({ depth: line.depth, box });
    } else {
      parent.appendChild(row);
    }
  });
}

// Hovering a drawn ray lights its lines; hovering a line lights its ray.
// `onRays` hears of the rays lit (none: back to the step's).
export function linkHover(panel, svg, onRays) {
  const light = (ray, on) => {
    for (const e of svg.querySelectorAll(`g.ray[data-ray="${ray}"]`)) e.classList.toggle("hot", on);
    for (const e of panel.querySelectorAll(`.line[data-ray="${ray}"]`)) e.classList.toggle("hot", on);
    onRays(on ? [ray] : null);
  };
  const hover = (root, selector) => {
    root.addEventListener("mouseover", (e) => {
      const at = e.target.closest(selector);
      if (at) light(at.dataset.ray, true);
    });
    root.addEventListener("mouseout", (e) => {
      const at = e.target.closest(selector);
      if (at) light(at.dataset.ray, false);
    });
  };
  hover(svg, "g.ray");
  hover(panel, ".line[data-ray]");
}

// Next and Back over the steps of the tree in `panel`: each step's lines
// and its ray marked `current`, its folds opened, `where` saying which.
export class Stepper {
  // `onStep` hears of each step's rays (none before the first step).
  constructor(panel, svg, back, next, where, onStep) {
    Object.assign(this, { panel, svg, back, next, where, onStep });
    this.rays = [];
    this.step = -1;
    this.count = 0;
    back.addEventListener("click", () => this.go(this.step - 1));
    next.addEventListener("click", () => this.go(this.step + 1));
  }

  // A new tree, of `lines`: before its first step.
  reset(lines) {
    this.count = lines.length ? lines[lines.length - 1].step + 1 : 0;
    this.go(-1);
  }

  go(step) {
    if (step < -1 || step >= this.count) return;
    this.step = step;
    for (const e of this.panel.querySelectorAll(".current")) e.classList.remove("current");
    for (const e of this.svg.querySelectorAll(".current")) e.classList.remove("current");
    this.svg.classList.toggle("stepping", step >= 0);
    const rows = [...this.panel.querySelectorAll(`.line[data-step="${step}"]`)];
    for (const row of rows) {
      row.classList.add("current");
      for (let d = row.closest("details"); d; d = d.parentElement.closest("details")) d.open = true;
      const ray = row.dataset.ray;
      if (ray !== undefined) {
        for (const g of this.svg.querySelectorAll(`g.ray[data-ray="${ray}"]`)) g.classList.add("current");
      }
    }
    this.rays = [...new Set(rows.map((r) => r.dataset.ray).filter((r) => r !== undefined))];
    this.onStep(this.rays);
    if (rows[0]) rows[0].scrollIntoView({ block: "nearest" });
    this.panel.dataset.step = step;
    this.back.disabled = step <= 0;
    this.next.disabled = step >= this.count - 1;
    const section = rows[0] && rows[0].dataset.section;
    this.where.textContent =
      step < 0 ? `${this.count} steps` : `step ${step + 1} of ${this.count}${section ? ` · ${SECTIONS[section]}` : ""}`;
  }
}
