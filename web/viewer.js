// printlight's HTML report: each model of the report (a prediction, the
// target, the per-voxel error) on its own rotating view, and the error per
// iteration of an optimisation run. The page carries its data in a JSON
// script element (id "printlight-data"): {title, summary, models: [{label,
// glb (base64)}], history: [{iteration, value}], historyLabel}.
import * as THREE from 'three';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';

function bytesOf(base64) {
  const text = atob(base64);
  const bytes = new Uint8Array(text.length);
  for (let i = 0; i < text.length; ++i) bytes[i] = text.charCodeAt(i);
  return bytes.buffer;
}

function addView(container, model, views) {
  const panel = document.createElement('figure');
  const canvas = document.createElement('canvas');
  const caption = document.createElement('figcaption');
  caption.textContent = model.label;
  panel.append(canvas, caption);
  container.append(panel);

  const renderer = new THREE.WebGLRenderer({ canvas, antialias: true });
  renderer.setPixelRatio(window.devicePixelRatio);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0x808080);
  const camera = new THREE.PerspectiveCamera(30, 1, 1e-4, 10);
  const controls = new OrbitControls(camera, canvas);
  controls.autoRotate = true;
  controls.autoRotateSpeed = 2;
  const view = { renderer, scene, camera, controls, canvas, ready: false };
  views.push(view);

  new GLTFLoader().parse(bytesOf(model.glb), '', (gltf) => {
    const root = gltf.scene;
    scene.add(root);
    const box = new THREE.Box3().setFromObject(root);
    const centre = box.getCenter(new THREE.Vector3());
    const radius = box.getSize(new THREE.Vector3()).length() / 2;
    const distance = radius / Math.sin(THREE.MathUtils.degToRad(camera.fov / 2));
    camera.position.copy(centre).add(new THREE.Vector3(0.6, -0.7, 0.5).normalize().multiplyScalar(distance));
    camera.up.set(0, 0, 1);
    camera.near = distance / 100;
    camera.far = distance * 10;
    camera.updateProjectionMatrix();
    controls.target.copy(centre);
    controls.update();
    view.ready = true;
    document.body.dataset.loaded = String(views.filter((v) => v.ready).length);
  }, (error) => {
    caption.textContent = model.label + ': cannot read the model (' + error + ')';
  });
}

function plotHistory(container, history, label) {
  if (!history || history.length === 0) return;
  const width = 480, height = 240, margin = 40;
  const xs = history.map((h) => h.iteration), ys = history.map((h) => h.value);
  const xMax = Math.max(1, ...xs), yMax = Math.max(...ys) * 1.1 || 1;
  const x = (v) => margin + (width - 2 * margin) * v / xMax;
  const y = (v) => height - margin - (height - 2 * margin) * v / yMax;
  const points = history.map((h) => `${x(h.iteration)},${y(h.value)}`).join(' ');
  const ns = 'http://www.w3.org/2000/svg';
  const svg = document.createElementNS(ns, 'svg');
  svg.setAttribute('width', width);
  svg.setAttribute('height', height);
  svg.innerHTML =
    `<polyline fill="none" stroke="#c33" stroke-width="2" points="${points}"/>` +
    `<line x1="${margin}" y1="${height - margin}" x2="${width - margin}" y2="${height - margin}" stroke="#000"/>` +
    `<line x1="${margin}" y1="${margin}" x2="${margin}" y2="${height - margin}" stroke="#000"/>` +
    `<text x="${width / 2}" y="${height - 8}" text-anchor="middle">iteration</text>` +
    `<text x="12" y="${margin - 12}">${label}</text>` +
    `<text x="${margin - 4}" y="${y(0)}" text-anchor="end">0</text>` +
    `<text x="${margin - 4}" y="${y(yMax / 1.1) + 4}" text-anchor="end">${(yMax / 1.1).toFixed(1)}</text>` +
    `<text x="${x(xMax)}" y="${height - margin + 16}" text-anchor="middle">${xMax}</text>`;
  container.append(svg);
}

function main() {
  const data = JSON.parse(document.getElementById('printlight-data').textContent);
  document.title = data.title;
  document.getElementById('title').textContent = data.title;
  document.getElementById('summary').textContent = data.summary || '';
  const views = [];
  const container = document.getElementById('views');
  for (const model of data.models) addView(container, model, views);
  plotHistory(document.getElementById('history'), data.history, data.historyLabel || '');
  // One view dragged turns them all: target, prediction and error stay
  // side by side from the same viewpoint.
  // (Only what a person drags is copied; the auto-rotation turns all
  // views alike from there.)
  let dragged = null;
  for (const v of views) {
    v.controls.addEventListener('start', () => { dragged = v; });
    v.controls.addEventListener('end', () => { dragged = null; });
    v.controls.addEventListener('change', () => {
      if (dragged !== v) return;
      for (const w of views)
        if (w !== v && w.ready) {
          w.camera.position.copy(v.camera.position);
          w.camera.zoom = v.camera.zoom;
          w.camera.updateProjectionMatrix();
          w.controls.target.copy(v.controls.target);
        }
    });
  }
  const animate = () => {
    for (const v of views) {
      const w = v.canvas.clientWidth, h = v.canvas.clientHeight;
      if (v.canvas.width !== w || v.canvas.height !== h) {
        v.renderer.setSize(w, h, false);
        v.camera.aspect = w / h;
        v.camera.updateProjectionMatrix();
      }
      v.controls.update();
      v.renderer.render(v.scene, v.camera);
    }
    requestAnimationFrame(animate);
  };
  animate();
}

main();
