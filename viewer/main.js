// The isoforge viewer: shows the .glb files listed in files.json (written by `isoforge view`)
// or opened from disk. Everything it loads is served from this directory: three.js, the Draco
// decoder (three/examples/jsm/libs/draco/gltf/) and the meshopt decoder.
//
// For tests and scripts the page publishes window.isoforgeViewer: {ready, error, triangles,
// meshes: [{name, file, triangles, segments, points, visible}], bbox: {min, max}, units,
// legends, modelRegion(), regionPixels(region)} (see docs/viewer.md).
//
// URL parameters (the figure gallery's links, docs/figures.md): glb=URL (repeatable) loads those
// files instead of files.json; view=X,Y,Z the camera direction from the model's centre;
// up=X,Y,Z the camera's up vector; opacity=MESH:ALPHA (repeatable) draws that mesh translucent;
// panel=0 hides the side panel.

import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { DRACOLoader } from 'three/addons/loaders/DRACOLoader.js';
import { MeshoptDecoder } from 'three/addons/libs/meshopt_decoder.module.js';

const BACKGROUND = 0x1e2126;
const params = new URLSearchParams(window.location.search);
const vectorParam = (name, fallback) => {
  const v = (params.get(name) || '').split(',').map(Number);
  return v.length === 3 && v.every(Number.isFinite) && v.some((x) => x !== 0) ? v : fallback;
};
const viewDirection = vectorParam('view', [0.6, 0.45, 1]);
const opacities = new Map(params.getAll('opacity').map((o) => {
  const i = o.lastIndexOf(':');
  return [o.slice(0, i), Number(o.slice(i + 1))];
}));
if (params.get('panel') === '0') document.getElementById('panel').style.display = 'none';

const state = {
  ready: false,
  error: null,
  triangles: 0,
  meshes: [],
  bbox: null,
  units: [],
  legends: [],
  modelRegion,
  regionPixels,
};
window.isoforgeViewer = state;

const view = document.getElementById('view');
const statusLine = document.getElementById('status');
const meshList = document.getElementById('meshes');
const legends = document.getElementById('legends');

// preserveDrawingBuffer: the screenshot button and regionPixels read the canvas after a frame.
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio);
renderer.setSize(view.clientWidth, view.clientHeight);
view.appendChild(renderer.domElement);

const scene = new THREE.Scene();
scene.background = new THREE.Color(BACKGROUND);
const camera = new THREE.PerspectiveCamera(35, view.clientWidth / view.clientHeight, 0.01, 1000);
camera.up.set(...vectorParam('up', [0, 1, 0]));
scene.add(new THREE.HemisphereLight(0xffffff, 0x444444, 1.6));
const headlight = new THREE.DirectionalLight(0xffffff, 2.0);
camera.add(headlight);
scene.add(camera);
const controls = new OrbitControls(camera, renderer.domElement);
controls.addEventListener('change', render);
const models = new THREE.Group();
scene.add(models);

const draco = new DRACOLoader().setDecoderPath('./three/examples/jsm/libs/draco/gltf/');
const loader = new GLTFLoader().setDRACOLoader(draco).setMeshoptDecoder(MeshoptDecoder);

function render() {
  renderer.render(scene, camera);
}

window.addEventListener('resize', () => {
  camera.aspect = view.clientWidth / view.clientHeight;
  camera.updateProjectionMatrix();
  renderer.setSize(view.clientWidth, view.clientHeight);
  render();
});

function setStatus(text, isError = false) {
  statusLine.textContent = text;
  statusLine.classList.toggle('error', isError);
}

// Counts of what an object draws: triangles (meshes), segments (lines), points.
function countPrimitives(root) {
  const counts = { triangles: 0, segments: 0, points: 0 };
  root.traverse((o) => {
    const g = o.geometry;
    if (!g) return;
    const n = g.index ? g.index.count : g.attributes.position.count;
    if (o.isMesh) counts.triangles += n / 3;
    else if (o.isLineSegments) counts.segments += n / 2;
    else if (o.isLine) counts.segments += Math.max(n - 1, 0);
    else if (o.isPoints) counts.points += n;
  });
  return counts;
}

// Material tweaks: both sides of open surfaces lit, points a few pixels wide.
function prepare(root) {
  root.traverse((o) => {
    if (o.isMesh) {
      o.material.side = THREE.DoubleSide;
      if (!o.geometry.attributes.normal) o.geometry.computeVertexNormals();
    } else if (o.isPoints) {
      o.material.size = 3;
      o.material.sizeAttenuation = false;
    }
  });
}

function fitView() {
  const box = new THREE.Box3();
  models.traverse((o) => {
    if (o.geometry && o.visible) box.expandByObject(o);
  });
  if (box.isEmpty()) return;
  const center = box.getCenter(new THREE.Vector3());
  const radius = Math.max(box.getSize(new THREE.Vector3()).length() / 2, 1e-9);
  const distance = radius / Math.sin(THREE.MathUtils.degToRad(camera.fov / 2)) * 1.05;
  camera.near = distance / 1000;
  camera.far = distance * 10;
  const toEye = new THREE.Vector3(...viewDirection).normalize();
  camera.position.copy(center).add(toEye.clone().multiplyScalar(distance));
  camera.lookAt(center);
  camera.updateMatrixWorld();
  // Closer where the box allows: every corner inside the view, with a 5% margin.
  const right = new THREE.Vector3().setFromMatrixColumn(camera.matrixWorld, 0);
  const up = new THREE.Vector3().setFromMatrixColumn(camera.matrixWorld, 1);
  const tanV = Math.tan(THREE.MathUtils.degToRad(camera.fov / 2)) / 1.05;
  const tanH = tanV * camera.aspect;
  let needed = 0;
  for (let i = 0; i < 8; ++i) {
    const v = new THREE.Vector3(i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y,
                                i & 4 ? box.max.z : box.min.z).sub(center);
    const z = v.dot(toEye);
    needed = Math.max(needed, z + Math.abs(v.dot(right)) / tanH, z + Math.abs(v.dot(up)) / tanV);
  }
  if (needed > 0 && needed < distance) {
    camera.position.copy(center).add(toEye.multiplyScalar(needed));
  }
  camera.updateProjectionMatrix();
  controls.target.copy(center);
  controls.update();
  render();
}

function updateSummary() {
  state.triangles = state.meshes.reduce((sum, m) => sum + m.triangles, 0);
  const box = new THREE.Box3().setFromObject(models);
  state.bbox = box.isEmpty() ? null : { min: box.min.toArray(), max: box.max.toArray() };
  const segments = state.meshes.reduce((sum, m) => sum + m.segments, 0);
  const points = state.meshes.reduce((sum, m) => sum + m.points, 0);
  const units = [...new Set(state.units)].join(', ');
  setStatus(`${state.meshes.length} mesh(es): ${state.triangles} triangles` +
            (segments ? `, ${segments} segments` : '') + (points ? `, ${points} points` : '') +
            (units ? `\nunits: ${units}` : ''));
}

function addLegend(legend, meshName) {
  state.legends.push({ mesh: meshName, ...legend });
  const div = document.createElement('div');
  div.className = 'legend';
  const title = document.createElement('div');
  title.className = 'title';
  title.textContent = `${legend.array || meshName} (${legend.colormap || 'colours'}${legend.log ? ', log' : ''})`;
  const bar = document.createElement('canvas');
  bar.width = 256;
  bar.height = 1;
  const ctx = bar.getContext('2d');
  const gradient = ctx.createLinearGradient(0, 0, 256, 0);
  const colors = legend.colors || [];
  colors.forEach((c, i) => {
    gradient.addColorStop(colors.length > 1 ? i / (colors.length - 1) : 0,
                          `rgba(${c[0]}, ${c[1]}, ${c[2]}, ${(c[3] ?? 255) / 255})`);
  });
  ctx.fillStyle = gradient;
  ctx.fillRect(0, 0, 256, 1);
  const range = document.createElement('div');
  range.className = 'range';
  const [lo, hi] = legend.range || [0, 1];
  range.innerHTML = `<span>${Number(lo).toPrecision(4)}</span><span>${Number(hi).toPrecision(4)}</span>`;
  div.append(title, bar, range);
  legends.appendChild(div);
}

function addMeshEntry(object, name, file) {
  const counts = countPrimitives(object);
  const entry = { name, file, visible: true, ...counts };
  state.meshes.push(entry);
  const li = document.createElement('li');
  const box = document.createElement('input');
  box.type = 'checkbox';
  box.checked = true;
  box.title = 'show or hide this mesh';
  box.addEventListener('change', () => {
    object.visible = box.checked;
    entry.visible = box.checked;
    render();
  });
  const label = document.createElement('span');
  label.textContent = name;
  const count = document.createElement('span');
  count.className = 'count';
  count.textContent = counts.triangles ? `${counts.triangles} tri` :
                      counts.segments ? `${counts.segments} seg` : `${counts.points} pts`;
  li.append(box, label, count);
  meshList.appendChild(li);
}

// Adds one parsed glTF: a list entry per node of its scene (one per isoforge mesh), with the
// names, units and legends from the JSON.
async function addGltf(gltf, file) {
  const json = gltf.parser.json;
  const sceneIndex = json.scene ?? 0;
  const sceneDef = (json.scenes || [])[sceneIndex] || { nodes: [] };
  if (sceneDef.extras && sceneDef.extras.units) state.units.push(sceneDef.extras.units);
  prepare(gltf.scene);
  models.add(gltf.scene);
  for (const nodeIndex of sceneDef.nodes || []) {
    const node = await gltf.parser.getDependency('node', nodeIndex);
    const def = json.nodes[nodeIndex];
    const meshDef = def.mesh !== undefined ? json.meshes[def.mesh] : null;
    const name = def.name || (meshDef && meshDef.name) || `${file} #${nodeIndex}`;
    addMeshEntry(node, name, file);
    if (opacities.has(name)) {
      node.traverse((o) => {
        if (!o.material) return;
        o.material.transparent = true;
        o.material.opacity = opacities.get(name);
        o.material.depthWrite = false;
      });
    }
    if (meshDef && meshDef.extras && meshDef.extras.legend) addLegend(meshDef.extras.legend, name);
  }
}

function applyWireframe() {
  const on = document.getElementById('wireframe').checked;
  models.traverse((o) => {
    if (o.isMesh) o.material.wireframe = on;
  });
  render();
}

async function loadUrl(url, file) {
  const gltf = await loader.loadAsync(url);
  await addGltf(gltf, file);
}

async function loadFiles(files) {
  for (const f of files) {
    const gltf = await loader.parseAsync(await f.arrayBuffer(), '');
    await addGltf(gltf, f.name);
  }
  applyWireframe();
  updateSummary();
  fitView();
}

// The screen rectangle (CSS pixels of the canvas) covered by the projected bounding box.
function modelRegion() {
  const box = new THREE.Box3().setFromObject(models);
  if (box.isEmpty()) return null;
  const rect = renderer.domElement.getBoundingClientRect();
  let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
  for (let i = 0; i < 8; ++i) {
    const p = new THREE.Vector3(i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y,
                                i & 4 ? box.max.z : box.min.z).project(camera);
    const x = (p.x + 1) / 2 * rect.width, y = (1 - p.y) / 2 * rect.height;
    x0 = Math.min(x0, x); x1 = Math.max(x1, x); y0 = Math.min(y0, y); y1 = Math.max(y1, y);
  }
  const clamp = (v, hi) => Math.min(Math.max(Math.round(v), 0), hi);
  return { x0: clamp(x0, rect.width), y0: clamp(y0, rect.height),
           x1: clamp(x1, rect.width), y1: clamp(y1, rect.height) };
}

// Of the rendered pixels in `region` (CSS pixels), how many differ from the background.
function regionPixels(region) {
  render();
  const src = renderer.domElement;
  const scale = src.width / src.getBoundingClientRect().width;
  const w = Math.max(1, Math.round((region.x1 - region.x0) * scale));
  const h = Math.max(1, Math.round((region.y1 - region.y0) * scale));
  const canvas = document.createElement('canvas');
  canvas.width = w;
  canvas.height = h;
  const ctx = canvas.getContext('2d');
  ctx.drawImage(src, Math.round(region.x0 * scale), Math.round(region.y0 * scale), w, h, 0, 0, w, h);
  const data = ctx.getImageData(0, 0, w, h).data;
  const [br, bgc, bb] = [(BACKGROUND >> 16) & 255, (BACKGROUND >> 8) & 255, BACKGROUND & 255];  // sRGB
  let differing = 0;
  for (let i = 0; i < data.length; i += 4) {
    if (Math.abs(data[i] - br) + Math.abs(data[i + 1] - bgc) + Math.abs(data[i + 2] - bb) > 24) ++differing;
  }
  return { total: w * h, differing };
}

document.getElementById('wireframe').addEventListener('change', applyWireframe);
document.getElementById('fit').addEventListener('click', fitView);
document.getElementById('screenshot').addEventListener('click', () => {
  render();
  const a = document.createElement('a');
  a.href = renderer.domElement.toDataURL('image/png');
  a.download = 'isoforge-view.png';
  a.click();
});
document.getElementById('open').addEventListener('change', (e) => {
  loadFiles([...e.target.files]).catch((err) => setStatus(String(err), true));
});

async function main() {
  let list = params.getAll('glb').map((url) => ({ url, name: url.split('/').pop() }));
  if (list.length === 0) {
    try {
      const response = await fetch('files.json');
      if (response.ok) list = await response.json();
    } catch {
      // opened from a plain directory: files come from the "open" button
    }
  }
  for (const f of list) await loadUrl(f.url, f.name);
  applyWireframe();
  updateSummary();
  fitView();
  if (list.length === 0) setStatus('no files: open a .glb');
  state.ready = true;
}

main().catch((err) => {
  state.error = String(err && err.stack ? err.stack : err);
  state.ready = true;
  setStatus(`error: ${err}`, true);
});
