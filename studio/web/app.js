// rosyhatch studio: the page. Draws the scene's mesh from the scene camera, the
// N-RoSy field as short crosses, singularities as dots with their ids, and sends
// every edit to the server (studio/server.h), which answers with the new field.
import * as THREE from '/three/build/three.module.js';
import { OrbitControls } from '/three/examples/jsm/controls/OrbitControls.js';

const params = new URLSearchParams(location.search);
const token = params.get('token') || '';
// The token stays in a cookie (set with the page); keep it out of the address bar.
if (token) history.replaceState(null, '', location.pathname);
const $ = (id) => document.getElementById(id);
const statusLine = $('status');

function setStatus(text, error = false) {
  statusLine.textContent = text;
  statusLine.className = error ? 'error' : '';
}

async function api(method, path, body) {
  const init = { method, headers: token ? { 'X-Rosy-Token': token } : {} };
  if (body !== undefined) {
    init.body = JSON.stringify(body);
    init.headers['Content-Type'] = 'application/json';
  }
  const res = await fetch(path, init);
  if (!res.ok) throw new Error((await res.text()).trim() || `HTTP ${res.status}`);
  return res;
}

// ---- scene ----------------------------------------------------------------
const canvas = $('canvas');
const renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio || 1);
renderer.setClearColor(0xf4f1ea);
const scene = new THREE.Scene();
scene.add(new THREE.AmbientLight(0xffffff, 0.35));
const light = new THREE.DirectionalLight(0xffffff, 0.75);
scene.add(light);
const camera = new THREE.PerspectiveCamera(30, 1, 0.01, 100);
camera.add(light);
light.position.set(-1, 1, 1);
scene.add(camera);
const controls = new OrbitControls(camera, canvas);
controls.enableDamping = false;

let state = null;
let meshObject = null, meshData = null;
let fieldLines = null, singularityGroup = new THREE.Group(), elementGroup = new THREE.Group();
let separatrixLines = null;
scene.add(singularityGroup, elementGroup);
let armLength = 0.01, dotRadius = 0.005;
let lastField = null;

function resize() {
  const w = canvas.clientWidth, h = canvas.clientHeight;
  renderer.setSize(w, h, false);
  camera.aspect = w / Math.max(1, h);
  camera.updateProjectionMatrix();
}
window.addEventListener('resize', () => { resize(); draw(); });

function draw() {
  renderer.render(scene, camera);
  placeLabels();
}
controls.addEventListener('change', draw);

function placeCamera(cam, bounds) {
  const pos = new THREE.Vector3(...cam.position), fwd = new THREE.Vector3(...cam.forward);
  const lo = new THREE.Vector3(...bounds.min), hi = new THREE.Vector3(...bounds.max);
  const centre = lo.clone().add(hi).multiplyScalar(0.5);
  const diag = lo.distanceTo(hi);
  const along = Math.max(centre.clone().sub(pos).dot(fwd), 1e-3 * diag);
  camera.position.copy(pos);
  camera.up.set(...cam.up);
  camera.fov = cam.fov;
  camera.near = Math.max(1e-4 * diag, along - 2 * diag > 0 ? (along - 2 * diag) : 1e-3 * diag);
  camera.far = along + 4 * diag;
  controls.target.copy(pos.clone().add(fwd.multiplyScalar(along)));
  camera.lookAt(controls.target);
  controls.update();
  resize();
}

// The mesh (the display mesh of a large one, docs/studio.md) arrives in pieces
// (chunked): once the positions are in, the faces received so far are drawn,
// piece by piece. `buffer` holds the whole answer; `got` bytes of it are in.
function meshArrived(buffer, got) {
  const view = new DataView(buffer);
  const nV = view.getUint32(4, true), nF = view.getUint32(8, true);
  if (got < 16 + 12 * nV) return;
  if (!meshObject) {
    const positions = new Float32Array(buffer, 16, 3 * nV);
    const indices = new Uint32Array(buffer, 16 + 12 * nV, 3 * nF);
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    geometry.setIndex(new THREE.BufferAttribute(indices, 1));
    const material = new THREE.MeshLambertMaterial({
      color: 0xd8d2c4, polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1 });
    meshObject = new THREE.Mesh(geometry, material);
    scene.add(meshObject);
    meshData = { nV, nF, positions, indices, shown: 0 };
  }
  const faces = Math.min(nF, Math.floor((got - 16 - 12 * nV) / 12));
  // Redrawn for each further quarter of the faces (the normals are recomputed each time).
  if (faces === meshData.shown || (faces < nF && faces - meshData.shown < nF / 4)) return;
  meshData.shown = faces;
  const geometry = meshObject.geometry;
  geometry.index.needsUpdate = true;
  geometry.setDrawRange(0, 3 * faces);
  geometry.computeVertexNormals();
  draw();
}

async function fetchMesh(onFirstPiece) {
  const res = await api('GET', '/api/mesh');
  const reader = res.body.getReader();
  let head = new Uint8Array(0), bytes = null, got = 0;
  for (;;) {
    const { done, value } = await reader.read();
    if (done) break;
    if (!bytes) {
      const joined = new Uint8Array(head.length + value.length);
      joined.set(head);
      joined.set(value, head.length);
      head = joined;
      if (head.length < 16) continue;
      const view = new DataView(head.buffer);
      const nV = view.getUint32(4, true), nF = view.getUint32(8, true), decimated = view.getUint32(12, true);
      bytes = new Uint8Array(16 + 12 * nV + 12 * nF + (decimated ? 4 * nV : 0));
      bytes.set(head.subarray(0, Math.min(head.length, bytes.length)));
      got = head.length;
      onFirstPiece();
    } else {
      bytes.set(value.subarray(0, Math.max(0, Math.min(value.length, bytes.length - got))), got);
      got += value.length;
    }
    meshArrived(bytes.buffer, got);
  }
  if (!bytes || got !== bytes.length) throw new Error('the mesh arrived incomplete');
  return bytes.buffer;
}

function finishMesh() {
  const { nV, nF, positions, indices } = meshData;
  // Arm length from the mean area per displayed vertex.
  let area = 0;
  const a = new THREE.Vector3(), b = new THREE.Vector3(), c = new THREE.Vector3();
  for (let f = 0; f < nF; ++f) {
    a.fromArray(positions, 3 * indices[3 * f]);
    b.fromArray(positions, 3 * indices[3 * f + 1]);
    c.fromArray(positions, 3 * indices[3 * f + 2]);
    area += b.sub(a).cross(c.sub(a)).length() / 2;
  }
  meshData.stride = Math.max(1, Math.round(nV / 6000)); // about 6000 crosses, whatever the mesh size
  armLength = 0.5 * Math.sqrt(area / (nV / meshData.stride));
  dotRadius = 1.1 * armLength;
}

// The field: N arms per displayed vertex, rotated about the vertex normal.
function buildField(buffer, offset = 0) {
  const view = new DataView(buffer, offset);
  const nV = view.getUint32(4, true), N = view.getUint32(8, true);
  const dirs = new Float32Array(buffer, offset + 16, 3 * nV);
  const normals = new Float32Array(buffer, offset + 16 + 12 * nV, 3 * nV);
  lastField = { N, dirs, normals };
  const stride = meshData.stride;
  const count = Math.ceil(nV / stride);
  const pos = new Float32Array(count * N * 6);
  const p = meshData.positions;
  let k = 0;
  const lift = 0.05 * armLength;
  for (let v = 0; v < nV; v += stride) {
    const dx = dirs[3 * v], dy = dirs[3 * v + 1], dz = dirs[3 * v + 2];
    if (dx === 0 && dy === 0 && dz === 0) continue;
    const nx = normals[3 * v], ny = normals[3 * v + 1], nz = normals[3 * v + 2];
    const ex = ny * dz - nz * dy, ey = nz * dx - nx * dz, ez = nx * dy - ny * dx; // n × d
    const ox = p[3 * v] + lift * nx, oy = p[3 * v + 1] + lift * ny, oz = p[3 * v + 2] + lift * nz;
    const arm = armLength * (N === 1 ? 1.2 : 0.6); // N arms from the vertex: a cross for N = 4
    for (let i = 0; i < N; ++i) {
      const t = (2 * Math.PI * i) / N, c = Math.cos(t), s = Math.sin(t);
      const ax = c * dx + s * ex, ay = c * dy + s * ey, az = c * dz + s * ez;
      pos[k++] = ox; pos[k++] = oy; pos[k++] = oz;
      pos[k++] = ox + arm * ax; pos[k++] = oy + arm * ay; pos[k++] = oz + arm * az;
    }
  }
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(pos.subarray(0, k), 3));
  if (fieldLines) { scene.remove(fieldLines); fieldLines.geometry.dispose(); }
  fieldLines = new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ color: 0x2a3550 }));
  scene.add(fieldLines);
}

function colourOf(numerator) {
  const strength = Math.min(1, 0.55 + 0.15 * (Math.abs(numerator) - 1));
  return numerator > 0 ? new THREE.Color(strength + 0.4, 0.12, 0.1) : new THREE.Color(0.1, 0.25, strength + 0.4);
}

function buildSingularities() {
  singularityGroup.clear ? singularityGroup.clear() : singularityGroup.children.slice().forEach((c) => singularityGroup.remove(c));
  const sphere = new THREE.SphereBufferGeometry(1, 12, 8);
  for (const s of state.singularities) {
    const m = new THREE.Mesh(sphere, new THREE.MeshBasicMaterial({ color: colourOf(s.index_numerator) }));
    m.position.set(...s.position);
    const r = dotRadius * (1 + 0.3 * (Math.abs(s.index_numerator) - 1));
    m.scale.set(r, r, r);
    m.userData = s;
    singularityGroup.add(m);
  }
  elementGroup.children.slice().forEach((c) => elementGroup.remove(c));
  const marker = new THREE.OctahedronBufferGeometry(1);
  state.elements.forEach((e, i) => {
    const m = new THREE.Mesh(marker, new THREE.MeshBasicMaterial({ color: e.order === 0 ? 0x1a8a3a : 0xb07a00 }));
    m.position.set(...e.position);
    m.scale.setScalar(1.5 * dotRadius); // larger than a dot: visible around its singularity
    m.userData = { element: i };
    elementGroup.add(m);
  });
  // Labels: one span per singularity, placed each frame.
  const labels = $('labels');
  labels.textContent = '';
  for (const s of state.singularities) {
    const span = document.createElement('span');
    span.textContent = String(s.id);
    labels.appendChild(span);
  }
}

const raycaster = new THREE.Raycaster();

// Screen position (CSS pixels in the canvas) of a world point with surface normal
// `normal`, and whether it is seen: `exact` casts a ray against the mesh (slow on
// big meshes: no BVH), else the normal only has to turn toward the camera (labels,
// every frame).
function screenOf(p, normal = null, exact = false) {
  const v = new THREE.Vector3(...p).project(camera);
  const x = (v.x + 1) / 2 * canvas.clientWidth, y = (1 - v.y) / 2 * canvas.clientHeight;
  let visible = v.z < 1 && x >= 0 && y >= 0 && x < canvas.clientWidth && y < canvas.clientHeight;
  if (visible && meshObject && exact) {
    const from = camera.position.clone(), to = new THREE.Vector3(...p);
    const dir = to.clone().sub(from);
    const dist = dir.length();
    raycaster.set(from, dir.normalize());
    const hit = raycaster.intersectObject(meshObject)[0];
    visible = !hit || hit.distance > dist - 2 * dotRadius;
  } else if (visible && normal) {
    visible = new THREE.Vector3(...normal).dot(camera.position.clone().sub(new THREE.Vector3(...p))) > 0;
  }
  return { x, y, visible };
}

function placeLabels() {
  if (!state) return;
  const spans = $('labels').children;
  state.singularities.forEach((s, i) => {
    const q = screenOf(s.position, s.normal);
    const span = spans[i];
    if (!span) return;
    span.style.display = q.visible ? 'block' : 'none';
    span.style.left = `${q.x}px`;
    span.style.top = `${q.y}px`;
  });
}

function updatePanel() {
  $('scene-name').textContent = state.scene;
  $('symmetry').value = String(state.symmetry);
  $('source').value = state.source;
  $('smoothing').value = state.smoothing_length;
  $('global-iterations').value = state.global_smoothing.iterations;
  const pos = state.singularities.filter((s) => s.index_numerator > 0).length;
  $('sing-count').textContent = String(state.singularities.length);
  $('sing-pos').textContent = String(pos);
  $('sing-neg').textContent = String(state.singularities.length - pos);
  $('index-sum').textContent = String(Math.round(state.index_sum * 1000) / 1000);
  $('undo').disabled = !state.can_undo;
  $('redo').disabled = !state.can_redo;
  const fmt = (v) => v.map((x) => x.toFixed(3)).join(', ');
  const list = $('elements');
  list.textContent = '';
  state.elements.forEach((e, i) => {
    const li = document.createElement('li');
    li.textContent = e.order === 0 ? `direction at (${fmt(e.position)})` : `singular ${e.order > 0 ? '+1' : '−1'} at (${fmt(e.position)})`;
    // The direction after adding: turn it about the surface normal (or drag from its
    // marker in the "direction" mode); a singular element's phase.
    if (e.order === 0) {
      for (const deg of [-15, 15]) {
        const b = document.createElement('button');
        b.textContent = deg < 0 ? '↻ 15°' : '↺ 15°';
        b.className = deg < 0 ? 'turn-cw' : 'turn-ccw';
        b.addEventListener('click', () => edit({ op: 'update_element', index: i, direction: turned(e, deg) }));
        li.appendChild(b);
      }
    } else {
      const label = document.createElement('label');
      label.textContent = ' phase ';
      const input = document.createElement('input');
      input.type = 'number'; input.step = '15'; input.value = String(e.phase); input.className = 'element-phase';
      input.addEventListener('change', () => edit({ op: 'update_element', index: i, phase: Number(input.value) || 0 }));
      label.appendChild(input);
      label.append('°');
      li.appendChild(label);
    }
    const del = document.createElement('button');
    del.textContent = 'delete';
    del.addEventListener('click', () => edit({ op: 'delete_element', index: i }));
    li.appendChild(del);
    list.appendChild(li);
  });
  const edits = $('edits');
  edits.textContent = '';
  state.edits.forEach((e, i) => {
    const li = document.createElement('li');
    li.textContent = e.op === 'move' ? `move ${e.id} to (${fmt(e.to)})` : e.op === 'cancel' ? `cancel ${e.ids.join(', ')}` : 'cancel pair';
    const del = document.createElement('button');
    del.textContent = 'delete';
    del.addEventListener('click', () => edit({ op: 'delete_edit', index: i }));
    li.appendChild(del);
    edits.appendChild(li);
  });
}

// The surface normal nearest to a point: the normal sent with the field at the
// closest displayed vertex.
function normalNear(p) {
  if (!lastField || !meshData) return null;
  const P = meshData.positions;
  let best = -1, bestD = Infinity;
  for (let v = 0; v < meshData.nV; ++v) {
    const d = (P[3 * v] - p[0]) ** 2 + (P[3 * v + 1] - p[1]) ** 2 + (P[3 * v + 2] - p[2]) ** 2;
    if (d < bestD) { bestD = d; best = v; }
  }
  return best < 0 ? null : new THREE.Vector3().fromArray(lastField.normals, 3 * best);
}
// A direction element's direction turned by `deg` degrees about the surface normal
// at the element (the state's `normal`: its face on the full mesh), counter-clockwise
// seen from outside, in the tangent plane.
function turned(e, deg) {
  const n = e.normal ? new THREE.Vector3(...e.normal) : normalNear(e.position);
  const d = new THREE.Vector3(...e.direction);
  if (!n || n.lengthSq() === 0) return d.toArray();
  d.sub(n.clone().multiplyScalar(d.dot(n))).normalize();
  return d.applyAxisAngle(n, (deg * Math.PI) / 180).toArray();
}

async function refreshSeparatrices() {
  if (separatrixLines) { scene.remove(separatrixLines); separatrixLines = null; }
  if (!$('show-separatrices').checked) return draw();
  const data = await (await api('GET', '/api/separatrices')).json();
  const pts = [], cols = [];
  for (const s of data.separatrices) {
    const c = s.incoming ? [0.95, 0.55, 0.1] : [0.1, 0.6, 0.2];
    for (let i = 0; i + 1 < s.points.length; ++i) {
      pts.push(...s.points[i], ...s.points[i + 1]);
      cols.push(...c, ...c);
    }
  }
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.Float32BufferAttribute(pts, 3));
  g.setAttribute('color', new THREE.Float32BufferAttribute(cols, 3));
  separatrixLines = new THREE.LineSegments(g, new THREE.LineBasicMaterial({ vertexColors: THREE.VertexColors }));
  scene.add(separatrixLines);
  draw();
}

// An edit response: "RSE1", JSON length, JSON, then the field.
function takeEditResponse(buffer) {
  const view = new DataView(buffer);
  const len = view.getUint32(4, true);
  state = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, 8, len)));
  buildField(buffer, 8 + len);
  buildSingularities();
  updatePanel();
  draw();
  if ($('show-separatrices').checked) refreshSeparatrices();
  schedulePreview();
}

let busy = false;
async function send(path, body) {
  if (busy) return false;
  busy = true;
  const t0 = performance.now();
  try {
    const res = await api('POST', path, body);
    takeEditResponse(await res.arrayBuffer());
    setStatus(`${state.singularities.length} singularities — updated in ${Math.round(performance.now() - t0)} ms`);
    return true;
  } catch (e) {
    setStatus(e.message, true);
    return false;
  } finally {
    busy = false;
  }
}
const edit = (body) => send('/api/edit', body);

// ---- preview ----------------------------------------------------------------
let previewTimer = null, previewUrl = null;
function schedulePreview() {
  if (!$('auto-preview').checked) return;
  clearTimeout(previewTimer);
  previewTimer = setTimeout(preview, 700);
}
async function preview() {
  try {
    const t0 = performance.now();
    const blob = await (await api('POST', '/api/preview?size=512')).blob();
    if (previewUrl) URL.revokeObjectURL(previewUrl);
    previewUrl = URL.createObjectURL(blob);
    $('preview').src = previewUrl;
    $('preview').dataset.ms = String(Math.round(performance.now() - t0));
    await previewOriginal();
  } catch (e) {
    setStatus(e.message, true);
  }
}
// The original (the field the scene file gave) beside the edited preview, as
// `rosyhatch compare --variants original,edited`; fetched once, it never changes.
let originalUrl = null;
async function previewOriginal() {
  const on = $('preview-original').checked;
  $('original-figure').hidden = !on;
  $('preview-caption').hidden = !on;
  if (!on || originalUrl) return;
  const blob = await (await api('POST', '/api/preview?size=512&of=original')).blob();
  originalUrl = URL.createObjectURL(blob);
  $('preview-original-img').src = originalUrl;
}
$('preview-button').addEventListener('click', preview);
$('preview-original').addEventListener('change', () => previewOriginal().catch((e) => setStatus(e.message, true)));

// ---- pointing ----------------------------------------------------------------
let pending = null; // first singularity picked (cancel / move)
let down = null;
function ndc(event) {
  const r = canvas.getBoundingClientRect();
  return new THREE.Vector2(((event.clientX - r.left) / r.width) * 2 - 1, -((event.clientY - r.top) / r.height) * 2 + 1);
}
function pick(event, objects) {
  raycaster.setFromCamera(ndc(event), camera);
  const hit = raycaster.intersectObjects(objects, false)[0] || null;
  if (hit) hit.ray = raycaster.ray.clone();
  return hit;
}
// The point of the true surface under a pick on the mesh. A display mesh (large
// meshes) lies off the surface by up to a clustering cell, so the server casts the
// same ray against the full mesh; null when that ray misses it.
async function surfacePoint(hit) {
  if (!hit) return null;
  if (!state.display || !state.display.decimated) return hit.point.toArray();
  const res = await api('POST', '/api/pick', { origin: hit.ray.origin.toArray(), direction: hit.ray.direction.toArray() });
  const r = await res.json();
  return r.hit ? r.position : null;
}
const mode = () => document.querySelector('input[name=mode]:checked').value;
for (const radio of document.querySelectorAll('input[name=mode]'))
  radio.addEventListener('change', () => { pending = null; controls.enabled = mode() === 'orbit' || mode() === 'cancel' || mode() === 'move'; });
// Orbiting stays on in the pointing modes except while adding a direction by dragging.

canvas.addEventListener('pointerdown', (event) => {
  down = { x: event.clientX, y: event.clientY, hit: null, grabbed: null };
  if (mode() === 'regular' && meshObject) {
    // A drag from a direction element's marker re-aims it; elsewhere it adds one.
    const marker = pick(event, [...elementGroup.children, meshObject]);
    const i = marker && marker.object !== meshObject ? marker.object.userData.element : undefined;
    if (i !== undefined && state.elements[i].order === 0) down.element = i;
    else down.hit = pick(event, [meshObject]);
  }
  if (mode() === 'move' && meshObject && !pending) {
    // Drag a singularity or an element marker to where it should go.
    // Elements first: a singular element has its singularity right under it.
    const hit = pick(event, [...elementGroup.children, meshObject]) || {};
    const dot = hit.object && hit.object !== meshObject ? hit : pick(event, [...singularityGroup.children, meshObject]);
    if (dot && dot.object !== meshObject) {
      down.grabbed = dot.object.userData;
      controls.enabled = false;
    }
  }
});
canvas.addEventListener('pointerup', async (event) => {
  if (!down || !state) return;
  const moved = Math.hypot(event.clientX - down.x, event.clientY - down.y);
  const m = mode();
  if (m === 'move' && down.grabbed) {
    controls.enabled = true;
    const grabbed = down.grabbed;
    down = null;
    if (moved > 4) {
      const target = await surfacePoint(pick(event, [meshObject]));
      if (!target) return setStatus('dropped off the model');
      if (grabbed.element !== undefined) return edit({ op: 'update_element', index: grabbed.element, position: target });
      return edit({ op: 'move_singularity', id: grabbed.id, to: target });
    }
    pending = grabbed; // a click: the next click on the model is the target
    return setStatus(grabbed.element !== undefined ? `element ${grabbed.element} picked; click where it should go`
                                                   : `singularity ${grabbed.id} picked; click where it should go`);
  }
  if (m === 'regular' && down.element !== undefined) {
    const i = down.element, from = new THREE.Vector3(...state.elements[i].position);
    down = null;
    if (moved <= 4) return setStatus(`drag from element ${i} to set its direction`);
    const end = pick(event, [meshObject]);
    if (!end) return setStatus('dragged off the model');
    return edit({ op: 'update_element', index: i, direction: end.point.clone().sub(from).toArray() });
  }
  if (m === 'regular' && down.hit) {
    // Drag sets the direction; a click takes the field's own direction there.
    const hit = down.hit, p = hit.point;
    down = null;
    let direction = null;
    if (moved > 4) {
      const end = pick(event, [meshObject]);
      if (end) direction = end.point.clone().sub(p).toArray();
    }
    if (!direction) {
      const v = meshData.indices[3 * hit.faceIndex];
      direction = lastField ? Array.from(lastField.dirs.subarray(3 * v, 3 * v + 3)) : [1, 0, 0];
      if (direction.every((x) => x === 0)) direction = [1, 0, 0];
    }
    const position = await surfacePoint(hit);
    if (!position) return setStatus('clicked off the model');
    return edit({ op: 'add_element', position, order: 0, direction });
  }
  if (moved > 4) { down = null; return; } // an orbit drag
  down = null;
  if (m === 'plus' || m === 'minus') {
    const position = await surfacePoint(pick(event, [meshObject]));
    if (position) edit({ op: 'add_element', position, order: m === 'plus' ? 1 : -1, phase: Number($('phase').value) || 0 });
  } else if (m === 'cancel' || m === 'move') {
    const dot = pick(event, [...singularityGroup.children, meshObject]);
    const s = dot && dot.object !== meshObject ? dot.object.userData : null;
    if (m === 'cancel') {
      if (!s) return setStatus('click a singularity (a dot)');
      if (!pending) { pending = s; return setStatus(`singularity ${s.id} picked; now one of opposite sign`); }
      const a = pending; pending = null;
      if (a.id === s.id) return setStatus('picked the same singularity twice');
      edit({ op: 'cancel', a: a.id, b: s.id });
    } else if (pending) {
      const from = pending; pending = null;
      const target = await surfacePoint(pick(event, [meshObject]));
      if (!target) return setStatus('clicked off the model');
      if (from.element !== undefined) edit({ op: 'update_element', index: from.element, position: target });
      else edit({ op: 'move_singularity', id: from.id, to: target });
    }
  }
});

// ---- panel ----------------------------------------------------------------
for (let n = 1; n <= 12; ++n) {
  const o = document.createElement('option');
  o.value = o.textContent = String(n);
  $('symmetry').appendChild(o);
}
$('symmetry').addEventListener('change', () => edit({ op: 'set', symmetry: Number($('symmetry').value) }));
$('source').addEventListener('change', () => edit({ op: 'set', source: $('source').value }));
$('smoothing').addEventListener('change', () => edit({ op: 'set', smoothing_length: Number($('smoothing').value) }));
$('global-iterations').addEventListener('change', () => edit({ op: 'set', global_smoothing_iterations: Math.round(Number($('global-iterations').value)) }));
$('show-separatrices').addEventListener('change', refreshSeparatrices);
$('undo').addEventListener('click', () => send('/api/undo'));
$('redo').addEventListener('click', () => send('/api/redo'));
$('save').addEventListener('click', async () => {
  try {
    const name = $('save-name').value.trim();
    const res = await api('POST', '/api/save' + (name ? `?name=${encodeURIComponent(name)}` : ''));
    const { path } = await res.json();
    $('save-result').textContent = `saved ${path}`;
    $('save-result').dataset.path = path;
  } catch (e) {
    $('save-result').textContent = e.message;
  }
});

// ---- start ----------------------------------------------------------------
async function start() {
  const t0 = performance.now();
  // The state first (the camera), then the mesh drawn as it streams in, and the field.
  state = await (await api('GET', '/api/state')).json();
  const base = state.scene.split('/').pop().replace(/\.ya?ml$/, '');
  $('save-name').value = `${base}-studio.yaml`;
  const field = api('GET', '/api/field').then((r) => r.arrayBuffer());
  await fetchMesh(() => placeCamera(state.camera, state.bounds));
  finishMesh();
  buildField(await field);
  buildSingularities();
  updatePanel();
  draw();
  const ms = Math.round(performance.now() - t0);
  document.body.dataset.loaded = String(ms);
  const shown = state.display.decimated ? ` (shown as ${state.display.faces} faces)` : '';
  setStatus(`${state.vertices} vertices, ${state.faces} faces${shown}, ${state.singularities.length} singularities — loaded in ${ms} ms`);
  schedulePreview();
}

// For tests and scripts: where the visible singularities are on screen.
window.studio = {
  singularitiesOnScreen: () => state.singularities.map((s) => ({ ...s, ...screenOf(s.position, null, true) })),
  elementsOnScreen: () => state.elements.map((e) => ({ ...e, ...screenOf(e.position, null, true) })),
  state: () => state,
  screenOf: (p) => screenOf(p),
};
start().catch((e) => setStatus(e.message, true));
