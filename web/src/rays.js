// The explained pixel's rays drawn over the image: an SVG laid on the
// canvas, in the image's own pixels (its viewBox the full image's size),
// drawing what the core worked out (`drawing` of `tracer explain --json`:
// each ray's part in the image, projected by the render's camera). No
// projection here: only lines, rings and marks where the core says.

const SVG = "http://www.w3.org/2000/svg";

// The colours of `tracer explain --draw`, one a kind of ray.
export const COLOURS = {
  primary: "rgb(255,214,0)",
  reflected: "rgb(0,190,255)",
  refracted: "rgb(90,230,110)",
  bounce: "rgb(255,140,0)",
  shadow: "rgb(255,255,255)",
  blocked: "rgb(255,40,40)",
  light: "rgb(255,245,150)",
};

const colourOf = (ray) => (ray.kind === "shadow" && ray.blocked ? COLOURS.blocked : COLOURS[ray.kind]);

function el(name, attributes, parent) {
  const e = document.createElementNS(SVG, name);
  for (const [k, v] of Object.entries(attributes)) e.setAttribute(k, v);
  if (parent) parent.appendChild(e);
  return e;
}

// Draws `drawing` on `svg`, whose box is the canvas's: marks keep their
// size on screen (`unit` image pixels to a CSS pixel).
export function drawRays(svg, drawing) {
  const [w, h] = drawing.size;
  svg.replaceChildren();
  svg.setAttribute("viewBox", `0 0 ${w} ${h}`);
  svg.setAttribute("preserveAspectRatio", "none");
  // `hidden` is an HTML element's property, not an SVG one's: the attribute.
  svg.removeAttribute("hidden");
  const shown = svg.getBoundingClientRect();
  const unit = shown.width > 0 ? w / shown.width : 1;
  const ring = 6 * unit;
  for (const ray of drawing.rays) {
    const g = el("g", { class: `ray ${ray.kind}${ray.blocked ? " blocked" : ""}`, "data-ray": ray.id }, svg);
    const title = el("title", {}, g);
    title.textContent = describe(ray);
    const s = ray.image;
    if (!s) continue;
    const ends = { x1: s.from[0], y1: s.from[1], x2: s.to[0], y2: s.to[1] };
    const dash = ray.blocked ? { "stroke-dasharray": `${6 * unit} ${4 * unit}` } : {};
    el("line", { ...ends, class: "halo", ...dash }, g);
    el("line", { ...ends, class: "stroke", stroke: colourOf(ray), ...dash }, g);
    // A wide, unseen line: what the mouse finds.
    el("line", { ...ends, class: "grip" }, g);
    if (s.leaves) arrow(g, s.from, s.to, colourOf(ray), 8 * unit);
    if (ray.kind !== "shadow" && s.end_seen) {
      const [cx, cy] = s.end_seen;
      el("circle", { cx, cy, r: ring, class: "hit", stroke: colourOf(ray) }, g);
      el("circle", { cx, cy, r: 1.2 * unit, class: "dot", fill: colourOf(ray) }, g);
    }
    const b = ray.blocked_by;
    if (b && b.seen_at) {
      const [x, y] = b.seen_at;
      const r = 5 * unit;
      el("path", { d: `M${x - r},${y - r}L${x + r},${y + r}M${x - r},${y + r}L${x + r},${y - r}`, class: "cross" }, g);
      const label = el("text", { x: x + r, y: y - r - 2 * unit, class: "blocker", "font-size": 12 * unit }, g);
      label.textContent = b.name;
    }
  }
  for (const light of drawing.lights) {
    if (!light.seen_at) continue;
    const [cx, cy] = light.seen_at;
    const g = el("g", { class: "light", "data-light": light.light }, svg);
    el("title", {}, g).textContent = `lights[${light.light}]`;
    for (let k = 0; k < 8; k++) {
      const a = (k * Math.PI) / 4;
      const [dx, dy] = [Math.cos(a) * 10 * unit, Math.sin(a) * 10 * unit];
      el("line", { x1: cx, y1: cy, x2: cx + dx, y2: cy + dy, class: "sunray" }, g);
    }
    el("circle", { cx, cy, r: 5 * unit, class: "sun" }, g);
  }
}

// A filled triangle at `to`, pointing away from `from`: the ray goes on
// out of the image.
function arrow(g, from, to, colour, size) {
  const [dx, dy] = [to[0] - from[0], to[1] - from[1]];
  const len = Math.hypot(dx, dy) || 1;
  const [ax, ay] = [dx / len, dy / len];
  const [bx, by] = [to[0] - ax * size, to[1] - ay * size];
  const [px, py] = [-ay * size * 0.5, ax * size * 0.5];
  const points = `${to[0]},${to[1]} ${bx + px},${by + py} ${bx - px},${by - py}`;
  el("polygon", { points, class: "arrow", fill: colour }, g);
}

function describe(ray) {
  const words = {
    primary: "primary ray",
    reflected: "mirror ray",
    refracted: "refracted ray",
    bounce: "the path's bounce",
    shadow: "shadow ray",
  }[ray.kind];
  if (ray.kind !== "shadow") return words;
  const to = ray.light === null || ray.light === undefined ? "a light" : `lights[${ray.light}]`;
  if (!ray.blocked) return `${words} to ${to}: clear`;
  return `${words} to ${to}: blocked${ray.blocked_by ? ` by ${ray.blocked_by.name}` : ""}`;
}

// The legend: only the kinds drawn.
export function legend(box, drawing) {
  box.replaceChildren();
  const drawn = drawing.rays.filter((r) => r.image);
  const items = [
    ["primary", "primary ray", (r) => r.kind === "primary"],
    ["reflected", "mirror ray", (r) => r.kind === "reflected"],
    ["refracted", "refracted ray", (r) => r.kind === "refracted"],
    ["bounce", "path's bounce", (r) => r.kind === "bounce"],
    ["shadow", "shadow ray, clear", (r) => r.kind === "shadow" && !r.blocked],
    ["blocked", "shadow ray, blocked", (r) => r.blocked],
  ];
  for (const [key, words, has] of items) {
    if (!drawn.some(has)) continue;
    const item = document.createElement("span");
    item.className = `key ${key}`;
    item.style.setProperty("--colour", COLOURS[key]);
    item.textContent = words;
    box.appendChild(item);
  }
  if (drawing.lights.some((l) => l.seen_at)) {
    const item = document.createElement("span");
    item.className = "key light";
    item.textContent = "light";
    box.appendChild(item);
  }
  if (drawn.some((r) => r.image.leaves)) {
    const item = document.createElement("span");
    item.className = "key leaves";
    item.textContent = "▶ leaves the image";
    box.appendChild(item);
  }
  box.hidden = false;
}
