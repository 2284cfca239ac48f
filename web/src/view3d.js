// The explained pixel in 3D, beside the image, turned with the mouse
// (three.js and its OrbitControls): the scene's shapes as the core
// prepared them (`scene` of `tracer_explain_view`: each object's spheres
// and triangles, no scene read here), the camera with its image plane and
// the clicked pixel on it, the lights, and the same rays as over the
// image, in the same colours.

import * as THREE from "three";
import { OrbitControls } from "three/examples/jsm/controls/OrbitControls.js";
import { COLOURS } from "./rays.js";

const colourOf = (ray) => (ray.kind === "shadow" && ray.blocked ? COLOURS.blocked : COLOURS[ray.kind]);
const v3 = (a) => new THREE.Vector3(a[0], a[1], a[2]);

export class View3d {
  constructor(box) {
    this.box = box;
    this.renderer = null;
    this.rays = new Map();
  }

  // The WebGL context, made on first use (a page that never explains a
  // pixel holds none).
  start() {
    if (this.renderer) return;
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.box.appendChild(this.renderer.domElement);
    this.camera = new THREE.PerspectiveCamera(45, 1, 0.01, 1000);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.addEventListener("change", () => this.draw());
    new ResizeObserver(() => this.fit()).observe(this.box);
  }

  fit() {
    const w = this.box.clientWidth;
    const h = this.box.clientHeight;
    if (!w || !h) return;
    this.renderer.setSize(w, h);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.draw();
  }

  draw() {
    if (this.scene) this.renderer.render(this.scene, this.camera);
  }

  // Shows `view.scene` and `view.drawing`; the viewpoint is kept while
  // the same scene's pixels are explained.
  show(view, keepViewpoint) {
    this.box.hidden = false;
    this.start();
    const { scene: shapes, drawing } = view;
    const scene = new THREE.Scene();
    scene.background = new THREE.Color(0x20242a);
    const [lo, hi] = shapes.bounds.map(v3);
    const centre = lo.clone().add(hi).multiplyScalar(0.5);
    const size = Math.max(hi.clone().sub(lo).length(), 1e-3);
    scene.add(new THREE.AmbientLight(0xffffff, 0.55));
    const headlight = new THREE.DirectionalLight(0xffffff, 1.6);
    this.camera.add(headlight);
    scene.add(this.camera);
    for (const object of shapes.objects) scene.add(this.object(object));
    scene.add(this.tracerCamera(shapes.camera, size));
    for (const light of drawing.lights) {
      const r = Math.max(light.radius, size / 120);
      const sun = new THREE.Mesh(new THREE.SphereGeometry(r, 12, 8), new THREE.MeshBasicMaterial({ color: COLOURS.light }));
      sun.position.copy(v3(light.position));
      scene.add(sun);
    }
    this.rays = new Map();
    for (const ray of drawing.rays) {
      const end = ray.end ? v3(ray.end) : v3(ray.origin).add(v3(ray.direction).multiplyScalar(size));
      const geometry = new THREE.BufferGeometry().setFromPoints([v3(ray.origin), end]);
      const material = ray.blocked
        ? new THREE.LineDashedMaterial({ color: colourOf(ray), dashSize: size / 80, gapSize: size / 120, transparent: true })
        : new THREE.LineBasicMaterial({ color: colourOf(ray), transparent: true });
      const line = new THREE.Line(geometry, material);
      if (ray.blocked) line.computeLineDistances();
      scene.add(line);
      this.rays.set(String(ray.id), line);
    }
    this.box.dataset.objects = shapes.objects.length;
    this.box.dataset.rays = drawing.rays.length;
    this.camera.near = size / 1000;
    this.camera.far = size * 20;
    if (!keepViewpoint) {
      // From beside and above the tracer's eye, far enough to hold the
      // scene and the eye, toward the scene's middle.
      const dir = v3(shapes.camera.eye).sub(centre).normalize();
      dir.applyAxisAngle(new THREE.Vector3(0, 1, 0), 0.7);
      dir.y += 0.5;
      this.camera.position.copy(centre).addScaledVector(dir.normalize(), size * 0.85);
      this.controls.target.copy(centre);
    }
    this.controls.update();
    this.scene = scene;
    this.fit();
  }

  object(object) {
    const colour = new THREE.Color(object.colour[0], object.colour[1], object.colour[2]);
    const material = new THREE.MeshLambertMaterial({
      color: colour,
      side: THREE.DoubleSide,
      transparent: object.glass,
      opacity: object.glass ? 0.35 : 1,
    });
    const group = new THREE.Group();
    group.name = object.name;
    for (const [centre, radius] of object.spheres) {
      const ball = new THREE.Mesh(new THREE.SphereGeometry(radius, 32, 16), material);
      ball.position.copy(v3(centre));
      group.add(ball);
    }
    if (object.triangles.length) {
      const positions = new Float32Array(object.triangles.flat(2));
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute("position", new THREE.BufferAttribute(positions, 3));
      geometry.computeVertexNormals();
      group.add(new THREE.Mesh(geometry, material));
    }
    return group;
  }

  // The eye, lines to the image plane's corners, the plane and the pixel.
  tracerCamera(camera, size) {
    const group = new THREE.Group();
    const eye = v3(camera.eye);
    const corners = camera.corners.map(v3);
    const points = [];
    for (const c of corners) points.push(eye, c);
    for (let k = 0; k < 4; k++) points.push(corners[k], corners[(k + 1) % 4]);
    const frame = new THREE.LineSegments(
      new THREE.BufferGeometry().setFromPoints(points),
      new THREE.LineBasicMaterial({ color: 0xdddddd }),
    );
    group.add(frame);
    const plane = new THREE.BufferGeometry().setFromPoints([corners[0], corners[1], corners[2], corners[0], corners[2], corners[3]]);
    group.add(new THREE.Mesh(plane, new THREE.MeshBasicMaterial({ color: 0x8899aa, transparent: true, opacity: 0.25, side: THREE.DoubleSide })));
    const dot = new THREE.Mesh(new THREE.SphereGeometry(size / 300, 8, 6), new THREE.MeshBasicMaterial({ color: COLOURS.primary }));
    dot.position.copy(v3(camera.pixel));
    group.add(dot);
    return group;
  }

  // Rays `ids` stand out (the others dimmed); none given: all as drawn.
  highlight(ids) {
    for (const [id, line] of this.rays) {
      line.material.opacity = ids.length === 0 || ids.includes(id) ? 1 : 0.2;
    }
    this.draw();
  }

  hide() {
    this.box.hidden = true;
    this.scene = null;
  }
}
