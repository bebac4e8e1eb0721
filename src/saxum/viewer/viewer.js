// saxum's results viewer: reads the data that saxum.view packed into this page and draws it
// with three.js (inlined next to it). No network: everything is in the page.
const errors = [];
window.saxumErrors = errors;
window.addEventListener('error', (e) => errors.push(String(e.message)));
window.addEventListener('unhandledrejection', (e) => errors.push(String(e.reason)));
const consoleError = console.error.bind(console);
console.error = (...args) => { errors.push(args.map(String).join(' ')); consoleError(...args); };

const $ = (id) => document.getElementById(id);
const data = JSON.parse($('saxum-data').textContent);
const raw = (() => {
  const text = atob($('saxum-binary').textContent.trim());
  const bytes = new Uint8Array(text.length);
  for (let i = 0; i < text.length; i++) bytes[i] = text.charCodeAt(i);
  return bytes;
})();
const TYPES = { f32: Float32Array, f64: Float64Array, i32: Int32Array, u32: Uint32Array,
  i16: Int16Array, u16: Uint16Array, u8: Uint8Array };
function arr(name) {
  const e = data.binary[name];
  return e ? new TYPES[e[0]](raw.buffer, e[1], e[2]) : null;
}
const LEVELS = 65535, UNIT = 32767;
const dequant = (level, lo, hi) => lo + level / LEVELS * (hi - lo);

const THREE = await import(URL.createObjectURL(
  new Blob([$('saxum-three').textContent], { type: 'text/javascript' })));

const dim = data.dim, nb = data.body.name.length, nf = data.time.length;
const p0 = arr('p0'), u = arr('u'), rot = arr('rotation');
const vertex = arr('vertex'), vstart = arr('vertex_start');
const FREE = 0;  // saxum.model.BodyKind.FREE
const moves = (b) => data.body.kind[b] === FREE || data.body.kind[b] === 3;  // or DEFORMABLE

// -- notes: what the page does not show, and a run that did not finish -----------------------
const notes = [];
if (data.status === 'running') {
  notes.push(['bad', `This run was still running when the page was written: it shows the ` +
    `${data.frame_count} frame(s) written by then, up to t = ${data.time[nf - 1].toPrecision(4)} s.`]);
} else if (data.status !== 'finished') {
  const why = data.message.startsWith(data.status) ? data.message
    : data.status + (data.message ? ` - ${data.message}` : '');
  notes.push(['bad', `This run did not finish (${why}). ` +
    `The page shows the ${data.frame_count} frame(s) it wrote, up to t = ` +
    `${data.time[nf - 1].toPrecision(4)} s.`]);
}
for (const d of data.damage) notes.push(['bad', `damaged file: ${d}`]);
if (data.every > 1) notes.push(['', `every ${data.every}th output frame of ${data.frame_count} (and the last)`]);
if (data.body.subset) notes.push(['', `blocks matching "${data.body.subset}" and the supports: ${nb} of ${data.body.total}`]);
if (data.overlay.stride > 1) {
  notes.push(['', `contact forces, hinges, sliding and open joints on every ${data.overlay.stride}th frame shown (page size)`]);
}
if (dim === 2) notes.push(['', `2D model: the section drawn as slabs; masses and forces per metre of depth`]);
$('heading').textContent = `${data.title} (saxum ${data.saxum})`;
for (const [cls, text] of notes) {
  const li = document.createElement('li');
  li.className = cls;
  li.textContent = text;
  $('notes').appendChild(li);
}

// -- scene ------------------------------------------------------------------------------------
const host = $('scene');
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio || 1);
host.appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0xf4f4f2);
const camera = new THREE.PerspectiveCamera(35, 1, 0.01, 1000);
const UP = dim === 3 ? new THREE.Vector3(0, 0, 1) : new THREE.Vector3(0, 1, 0);
// horizontal axes of the orbit: azimuth 0 looks from A (3D: +x; 2D: +z, the section's front)
const A = dim === 3 ? new THREE.Vector3(1, 0, 0) : new THREE.Vector3(0, 0, 1);
const B = dim === 3 ? new THREE.Vector3(0, 1, 0) : new THREE.Vector3(1, 0, 0);
camera.up.copy(UP);
scene.add(camera);
scene.add(new THREE.AmbientLight(0xffffff, 1.1));
const headlight = new THREE.DirectionalLight(0xffffff, 1.8);
headlight.position.set(0.4, 0.6, 1);
camera.add(headlight);

const lo = new THREE.Vector3(...data.box.lo), hi = new THREE.Vector3(...data.box.hi);
const centre = lo.clone().add(hi).multiplyScalar(0.5);
const radius = Math.max(hi.clone().sub(lo).length() / 2, 1e-6);
const sizes = [];
for (let b = 0; b < nb; b++) {
  let r = 0;
  for (let v = vstart[b]; v < vstart[b + 1]; v++) {
    let s = 0;
    for (let d = 0; d < dim; d++) s += vertex[v * dim + d] ** 2;
    r = Math.max(r, Math.sqrt(s));
  }
  sizes.push(r);
}
const freeSizes = sizes.filter((_, b) => moves(b)).sort((a, b) => a - b);
const blockSize = (freeSizes.length ? freeSizes : sizes.slice().sort((a, b) => a - b))[
  Math.floor((freeSizes.length || nb) / 2)] || radius / 10;
const depth = 2 * blockSize;  // slab depth of a 2D section [m]: drawing only

// -- blocks -----------------------------------------------------------------------------------
const edgeMaterial = new THREE.LineBasicMaterial({ color: 0x333333 });
const blocks = new THREE.Group();
scene.add(blocks);
const meshes = [];
const tri = arr('triangle'), tstart = arr('triangle_start');
for (let b = 0; b < nb; b++) {
  let geometry;
  if (dim === 3) {
    geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(
      vertex.slice(vstart[b] * 3, vstart[b + 1] * 3), 3));
    geometry.setIndex(Array.from(tri.subarray(tstart[b] * 3, tstart[b + 1] * 3)));
  } else {
    const shape = new THREE.Shape();
    for (let v = vstart[b]; v < vstart[b + 1]; v++) {
      const x = vertex[2 * v], y = vertex[2 * v + 1];
      if (v === vstart[b]) shape.moveTo(x, y); else shape.lineTo(x, y);
    }
    geometry = new THREE.ExtrudeGeometry(shape, { depth, bevelEnabled: false });
    geometry.translate(0, 0, -depth / 2);
  }
  const material = new THREE.MeshLambertMaterial({ flatShading: true, side: THREE.DoubleSide,
    polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1 });
  const mesh = new THREE.Mesh(geometry, material);
  mesh.userData.body = b;
  mesh.add(new THREE.LineSegments(new THREE.EdgesGeometry(geometry, 25), edgeMaterial));
  blocks.add(mesh);
  meshes.push(mesh);
}

// displacement [m] of body b at frame k, dequantized
const uLo = data.u_lo, uHi = data.u_hi;
function displacement(k, b, out) {
  const o = (k * nb + b) * 3;
  for (let d = 0; d < 3; d++) out[d] = dequant(u[o + d], uLo[d], uHi[d]);
  return out;
}
const moved = new Float32Array(nf * nb);
let largest = 0;
{
  const w = [0, 0, 0];
  for (let k = 0; k < nf; k++) {
    for (let b = 0; b < nb; b++) {
      displacement(k, b, w);
      const m = Math.hypot(w[0], w[1], w[2]);
      moved[k * nb + b] = m;
      if (moves(b) && m > largest) largest = m;
    }
  }
}

// -- colours ----------------------------------------------------------------------------------
const VIRIDIS = ['#440154', '#3b528b', '#21918c', '#5ec962', '#fde725'];
const MAGMA = ['#fcfdbf', '#fc8961', '#b73779', '#51127c', '#000004'];
const DAMAGE = ['#1a9850', '#e6ab02', '#000000'];
const GROUPS = ['#4e79a7', '#f28e2b', '#e15759', '#76b7b2', '#59a14f', '#edc948', '#b07aa1',
  '#ff9da7', '#9c755f', '#bab0ac'];
const SANDSTONE = new THREE.Color('#e3d5b8'), SUPPORT = new THREE.Color('#c8c8c8');
function ramp(stops, x) {
  const t = Math.min(Math.max(x, 0), 1) * (stops.length - 1);
  const i = Math.min(Math.floor(t), stops.length - 2);
  return new THREE.Color(stops[i]).lerp(new THREE.Color(stops[i + 1]), t - i);
}
const atRest = largest < 1e-6 * blockSize;
const damage = arr('damage'), stress = arr('stress');
const modes = { displacement: 'displacement [mm]', group: 'group' };
if (damage) modes.damage = 'joint damage [-]';
if (stress) modes.stress = 'largest compression [MPa]';
for (const [key, label] of Object.entries(modes)) {
  const o = document.createElement('option');
  o.value = key;
  o.textContent = label.replace(/ \[.*\]/, '');
  $('colour-by').appendChild(o);
}
const overlayFrames = data.overlay.frames;
const lastOverlay = (k) => {  // the overlay frame at or before k
  let j = -1;
  for (let i = 0; i < overlayFrames.length && overlayFrames[i] <= k; i++) j = i;
  return j;
};
function colourBlocks(k) {
  const mode = $('colour-by').value;
  const j = lastOverlay(k);
  for (let b = 0; b < nb; b++) {
    const c = meshes[b].material.color;
    if (mode === 'group') c.set(GROUPS[data.body.group[b] % GROUPS.length]);
    else if (!moves(b)) c.copy(SUPPORT);
    else if (mode === 'displacement') c.copy(atRest ? SANDSTONE : ramp(VIRIDIS, moved[k * nb + b] / largest));
    else if (mode === 'damage') c.copy(j < 0 ? SANDSTONE : ramp(DAMAGE, damage[j * nb + b] / LEVELS));
    else c.copy(ramp(MAGMA, stress[k * nb + b] / LEVELS));
  }
  legend(mode);
}
function legend(mode) {
  const stops = { displacement: VIRIDIS, damage: DAMAGE, stress: MAGMA }[mode];
  $('scale').style.display = stops ? '' : 'none';
  $('scale-labels').style.display = stops ? 'flex' : 'none';
  if (mode === 'group') {
    const used = [...new Set(data.body.group)];
    $('scale-title').innerHTML = used.map((g) => `<span style="color:${GROUPS[g % GROUPS.length]}">&#9632;</span> ${escapeHtml(data.groups[g])}`).join('<br>');
    return;
  }
  $('scale').style.background = `linear-gradient(to right, ${stops.join(',')})`;
  $('scale-title').textContent = modes[mode];
  $('scale-lo').textContent = '0';
  if (mode === 'displacement') {
    $('scale-hi').textContent = (largest * 1e3).toPrecision(3);
    if (atRest) {
      $('scale').style.display = 'none';
      $('scale-labels').style.display = 'none';
      $('scale-title').textContent = `at rest: largest displacement ${(largest * 1e3).toPrecision(2)} mm`;
    }
  } else if (mode === 'damage') {
    $('scale-hi').textContent = '1 (cracked)';
  } else {
    $('scale-hi').textContent = (data.colours.stress.max * 1e-6).toPrecision(3);
  }
}
function escapeHtml(s) {
  return s.replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' }[c]));
}

// -- contacts and mechanism: instanced dots, bars and diamonds --------------------------------
function packedPoints(name) {
  const box = data.overlay.boxes[name], levels = arr(name), start = arr(name + '_start');
  return { count: (j) => start[j + 1] - start[j], first: (j) => start[j],
    at: (i, out) => out.set(dequant(levels[3 * i], box.lo[0], box.hi[0]),
      dequant(levels[3 * i + 1], box.lo[1], box.hi[1]), dequant(levels[3 * i + 2], box.lo[2], box.hi[2])),
    most: () => { let m = 0; for (let j = 0; j + 1 < start.length; j++) m = Math.max(m, start[j + 1] - start[j]); return m; } };
}
function instanced(geometry, colour, count) {
  // drawn over the blocks: a contact point lies inside its joint, between two blocks
  const mesh = new THREE.InstancedMesh(geometry, new THREE.MeshLambertMaterial({ color: colour,
    depthTest: false }), Math.max(count, 1));
  mesh.renderOrder = 10;
  mesh.count = 0;
  mesh.frustumCulled = false;
  scene.add(mesh);
  return mesh;
}
const contact = packedPoints('contact'), opened = packedPoints('open');
const hinge = packedPoints('hinge'), sliding = packedPoints('sliding');
const force = arr('force');
const forceMax = data.overlay.force_max;
// the full-scale dot: the 90th percentile of the frames' largest forces, rounded up to 1, 2, 5
// (an impact lasts a step or two; as saxum.plot does)
const forceFull = (() => {
  const peaks = overlayFrames.map((_, j) => {
    let m = 0;
    for (let i = contact.first(j); i < contact.first(j) + contact.count(j); i++) m = Math.max(m, force[i]);
    return m / LEVELS * forceMax;
  }).sort((a, b) => a - b);
  const ref = peaks.length ? peaks[Math.min(peaks.length - 1, Math.floor(0.9 * peaks.length))] : 0;
  if (!(ref > 0)) return 0;
  const p = 10 ** Math.floor(Math.log10(ref));
  return [1, 2, 5, 10].map((m) => m * p).find((v) => v >= ref * (1 - 1e-12));
})();
const dot = 0.22 * blockSize;  // radius of the full-scale dot [m]
const dots = instanced(new THREE.SphereGeometry(1, 12, 8), 0xc0152f, contact.most());
const openMarks = instanced(new THREE.BoxGeometry(1, 1, 1), 0xe07b00, opened.most());
const hingeBars = instanced(new THREE.CylinderGeometry(1, 1, 1, 10), 0x111111, hinge.most() / 2);
const slideMarks = instanced(new THREE.OctahedronGeometry(1), 0x7b2cbf, sliding.most());
const matrix = new THREE.Matrix4(), quat = new THREE.Quaternion(), scale = new THREE.Vector3();
const pa = new THREE.Vector3(), pb = new THREE.Vector3(), Y = new THREE.Vector3(0, 1, 0);
function placeAll(mesh, points, j, size) {
  const n = j < 0 ? 0 : points.count(j);
  for (let i = 0; i < n; i++) {
    points.at(points.first(j) + i, pa);
    matrix.compose(pa, quat.identity(), scale.setScalar(size(points.first(j) + i)));
    mesh.setMatrixAt(i, matrix);
  }
  mesh.count = n;
  mesh.instanceMatrix.needsUpdate = true;
}
function showOverlays(k) {
  const j = overlayFrames.indexOf(k);  // only on frames that carry contacts
  const onC = $('show-contacts').checked && forceFull > 0, onM = $('show-mechanism').checked;
  placeAll(dots, contact, onC ? j : -1,
    (i) => dot * Math.sqrt(Math.min(force[i] / LEVELS * forceMax / forceFull, 1)));
  placeAll(openMarks, opened, onM ? j : -1, () => 0.12 * blockSize);
  placeAll(slideMarks, sliding, onM ? j : -1, () => 0.2 * blockSize);
  const n = onM && j >= 0 ? hinge.count(j) / 2 : 0;
  const r = 0.07 * blockSize;
  for (let i = 0; i < n; i++) {
    hinge.at(hinge.first(j) + 2 * i, pa);
    hinge.at(hinge.first(j) + 2 * i + 1, pb);
    const along = pb.clone().sub(pa), length = along.length();
    quat.setFromUnitVectors(Y, length > 0 ? along.divideScalar(length) : Y);
    matrix.compose(pa.add(pb).multiplyScalar(0.5), quat,
      scale.set(length > 0 ? r : 2 * r, Math.max(length, 2 * r), length > 0 ? r : 2 * r));
    hingeBars.setMatrixAt(i, matrix);
  }
  hingeBars.count = n;
  hingeBars.instanceMatrix.needsUpdate = true;
  const keys = [];
  if (onC) {
    const full = forceFull >= 1e6 ? [1e-6, 'M'] : forceFull >= 1e3 ? [1e-3, 'k'] : [1, ''];
    keys.push(`<span style="background:#c0152f"></span>contact force (dot area), largest ` +
      `${(forceFull * full[0]).toPrecision(3)} ${full[1]}${data.force_unit}`);
  }
  if (onM && j >= 0) {
    keys.push(`<span style="background:#111"></span>hinges (${n})`);
    keys.push(`<span style="background:#7b2cbf"></span>sliding (${sliding.count(j)})`);
    keys.push(`<span style="background:#e07b00"></span>open points (${opened.count(j)})`);
  } else if ((onM || onC) && j < 0) keys.push('no contacts stored for this frame');
  $('keys').innerHTML = keys.join('<br>');
}

// -- water ------------------------------------------------------------------------------------
let water = null;
if (data.water) {
  const w = data.water, ns = w.s.length, level = arr('water');
  const e = new THREE.Vector2(...w.direction), perp = new THREE.Vector2(-e.y, e.x);
  const across = [lo, hi].flatMap((p) => [lo, hi].map((q) => perp.x * p.x + perp.y * q.y));
  const c0 = Math.min(...across) - 0.25 * radius, c1 = Math.max(...across) + 0.25 * radius;
  const positions = new Float32Array(ns * 2 * 3), index = [];
  for (let i = 0; i + 1 < ns; i++) index.push(2 * i, 2 * i + 1, 2 * i + 2, 2 * i + 1, 2 * i + 3, 2 * i + 2);
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  geometry.setIndex(index);
  const mesh = new THREE.Mesh(geometry, new THREE.MeshBasicMaterial({ color: 0x5a9fd4,
    transparent: true, opacity: 0.35, side: THREE.DoubleSide, depthWrite: false }));
  mesh.frustumCulled = false;
  scene.add(mesh);
  const bottom = lo.y - 0.25 * radius;
  water = (k) => {
    for (let i = 0; i < ns; i++) {
      const h = level[k * ns + i], s = w.s[i];
      for (let side = 0; side < 2; side++) {
        const o = (2 * i + side) * 3;
        if (dim === 3) {
          const c = side ? c1 : c0;
          positions.set([s * e.x + c * perp.x, s * e.y + c * perp.y, h], o);
        } else {  // a curtain behind the slab, from below the blocks up to the surface
          positions.set([s, side ? h : Math.min(bottom, h), -0.55 * depth], o);
        }
      }
    }
    geometry.attributes.position.needsUpdate = true;
    mesh.visible = $('show-water').checked;
  };
} else {
  $('water-toggle').style.display = 'none';
}

// -- frames -----------------------------------------------------------------------------------
let frame = 0;
function setFrame(k) {
  frame = Math.max(0, Math.min(nf - 1, k));
  const w = [0, 0, 0];
  for (let b = 0; b < nb; b++) {
    displacement(frame, b, w);
    meshes[b].position.set(p0[3 * b] + w[0], p0[3 * b + 1] + w[1], p0[3 * b + 2] + w[2]);
    const r = (frame * nb + b) * 4;
    meshes[b].quaternion.set(rot[r + 1] / UNIT, rot[r + 2] / UNIT, rot[r + 3] / UNIT,
      rot[r] / UNIT).normalize();
  }
  colourBlocks(frame);
  showOverlays(frame);
  if (water) water(frame);
  $('slider').value = String(frame);
  const original = data.frames[frame];
  $('clock').textContent = `t = ${data.time[frame].toFixed(4)} s   step ${data.step[frame]}   ` +
    `frame ${original + 1} of ${data.frame_count}`;
  drawLog();
  drawInfo();
  render();
}

// -- camera: orbit about a target, pan, zoom --------------------------------------------------
const view = { target: centre.clone(), distance: 1, azimuth: -1.0, elevation: 0.4 };
function placeCamera() {
  const ce = Math.cos(view.elevation);
  const dir = A.clone().multiplyScalar(ce * Math.cos(view.azimuth))
    .addScaledVector(B, ce * Math.sin(view.azimuth)).addScaledVector(UP, Math.sin(view.elevation));
  camera.position.copy(view.target).addScaledVector(dir, view.distance);
  camera.near = view.distance / 1000;
  camera.far = view.distance * 100 + radius * 10;
  camera.lookAt(view.target);
  camera.updateProjectionMatrix();
}
function lookFrom(name) {
  if (name === 'fit') {
    view.target.copy(centre);
  } else {
    const dirs = { '+x': [1, 0, 0], '-x': [-1, 0, 0], '+y': [0, 1, 0], '-y': [0, -1, 0],
      '+z': [0, 0, 1], '-z': [0, 0, -1] };
    const d = name === 'iso'
      ? A.clone().multiplyScalar(Math.cos(-1.0)).addScaledVector(B, Math.sin(-1.0)).multiplyScalar(0.9).addScaledVector(UP, 0.45)
      : new THREE.Vector3(...dirs[name]);
    d.normalize();
    const limit = Math.PI / 2 - 1e-3;
    view.elevation = Math.max(-limit, Math.min(limit, Math.asin(d.dot(UP))));
    view.azimuth = Math.atan2(d.dot(B), d.dot(A));
    view.target.copy(centre);
  }
  // far enough that the box's bounding sphere fits the narrower side of the picture; a 2D
  // section seen from its front fits its width and height instead
  const tan = Math.tan(THREE.MathUtils.degToRad(camera.fov / 2)), aspect = Math.max(camera.aspect, 0.1);
  const half = hi.clone().sub(lo).multiplyScalar(0.5);
  view.distance = dim === 2 && name === '+z'
    ? 1.15 * Math.max(half.x / (tan * aspect), half.y / tan) + depth / 2
    : radius / Math.sin(Math.atan(tan * Math.min(aspect, 1))) * 1.05;
  placeCamera();
  render();
}
let drag = null;
renderer.domElement.addEventListener('contextmenu', (e) => e.preventDefault());
renderer.domElement.addEventListener('pointerdown', (e) => {
  drag = { x: e.clientX, y: e.clientY, x0: e.clientX, y0: e.clientY, pan: e.button === 2 || e.shiftKey };
  renderer.domElement.setPointerCapture(e.pointerId);
});
renderer.domElement.addEventListener('pointermove', (e) => {
  if (!drag) return;
  const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
  drag.x = e.clientX;
  drag.y = e.clientY;
  const h = renderer.domElement.clientHeight || 1;
  if (drag.pan) {
    const scaleM = 2 * view.distance * Math.tan(THREE.MathUtils.degToRad(camera.fov / 2)) / h;
    const right = new THREE.Vector3().setFromMatrixColumn(camera.matrix, 0);
    const up = new THREE.Vector3().setFromMatrixColumn(camera.matrix, 1);
    view.target.addScaledVector(right, -dx * scaleM).addScaledVector(up, dy * scaleM);
  } else {
    view.azimuth -= 4 * dx / h;
    view.elevation = Math.max(-1.55, Math.min(1.55, view.elevation + 4 * dy / h));
  }
  placeCamera();
  render();
});
renderer.domElement.addEventListener('pointerup', (e) => {
  if (drag && Math.hypot(e.clientX - drag.x0, e.clientY - drag.y0) < 4) pick(e);
  drag = null;
});
renderer.domElement.addEventListener('wheel', (e) => {
  e.preventDefault();
  view.distance *= Math.exp(0.0015 * Math.max(-300, Math.min(300, e.deltaY)));
  placeCamera();
  render();
}, { passive: false });
document.querySelectorAll('[data-view]').forEach((b) => b.addEventListener('click', () => lookFrom(b.dataset.view)));

// -- picking: a block's name, group, mass and displacement history ----------------------------
let selected = -1;
const raycaster = new THREE.Raycaster();
function pick(e) {
  const rect = renderer.domElement.getBoundingClientRect();
  const ndc = new THREE.Vector2((e.clientX - rect.left) / rect.width * 2 - 1,
    -(e.clientY - rect.top) / rect.height * 2 + 1);
  raycaster.setFromCamera(ndc, camera);
  const hit = raycaster.intersectObjects(meshes, false)[0];
  if (selected >= 0) meshes[selected].material.emissive.setHex(0x000000);
  selected = hit ? hit.object.userData.body : -1;
  if (selected >= 0) meshes[selected].material.emissive.setHex(0x553300);
  $('info').style.display = selected >= 0 ? 'block' : 'none';
  drawInfo();
  render();
}
const KINDS = ['free', 'fixed', 'driven', 'deformable'];
function drawInfo() {
  if (selected < 0) return;
  const b = selected;
  $('info-name').textContent = data.body.name[b];
  const rows = [['group', data.groups[data.body.group[b]]],
    ['kind', KINDS[data.body.kind[b]] || String(data.body.kind[b])],
    ['mass', `${data.body.mass[b].toPrecision(4)} ${data.mass_unit}`],
    ['displacement', `${(moved[frame * nb + b] * 1e3).toPrecision(3)} mm at t = ${data.time[frame].toFixed(3)} s`]];
  $('info-table').innerHTML = rows.map(([k, v]) => `<tr><td>${k}</td><td>${escapeHtml(v)}</td></tr>`).join('');
  const series = Array.from({ length: nf }, (_, k) => moved[k * nb + b] * 1e3);
  plotSeries($('info-plot'), [{ label: 'displacement [mm]', values: series, times: data.time }], data.time[frame]);
}

// -- solver log -------------------------------------------------------------------------------
const steps = data.steps;
function drawLog() {
  if (!steps.time) { $('log').style.display = 'none'; return; }
  const rows = [];
  // steps where the contact solver did not converge: red ticks on the sweeps' row
  if (steps.iterations) rows.push({ label: 'sweeps', values: steps.iterations, times: steps.time, failed: steps.converged });
  if (steps.error) rows.push({ label: 'error (log10)', values: steps.error.map((e) => Math.log10(Math.max(e, 1e-300))), times: steps.time });
  if (steps.kinetic_energy) rows.push({ label: `kinetic energy [J${dim === 2 ? '/m' : ''}]`, values: steps.kinetic_energy, times: steps.time });
  plotSeries($('log-plot'), rows, data.time[frame]);
}
function plotSeries(canvas, rows, now) {
  const ctx = canvas.getContext('2d'), W = canvas.width, H = canvas.height;
  ctx.clearRect(0, 0, W, H);
  ctx.font = '10px system-ui, sans-serif';
  const t0 = Math.min(data.time[0], ...rows.map((r) => r.times[0]));
  const t1 = Math.max(data.time[nf - 1], ...rows.map((r) => r.times[r.times.length - 1]));
  const X = (t) => 4 + (W - 8) * (t1 > t0 ? (t - t0) / (t1 - t0) : 0);
  const h = H / rows.length;
  rows.forEach((r, i) => {
    const finite = r.values.filter(Number.isFinite);
    const vlo = Math.min(...finite), vhi = Math.max(...finite);
    const Yv = (v) => i * h + h - 4 - (h - 16) * (vhi > vlo ? (v - vlo) / (vhi - vlo) : 0.5);
    ctx.strokeStyle = '#ddd';
    ctx.strokeRect(2, i * h + 1, W - 4, h - 2);
    ctx.strokeStyle = '#2b5d8a';
    ctx.beginPath();
    r.values.forEach((v, k) => { if (Number.isFinite(v)) ctx[k ? 'lineTo' : 'moveTo'](X(r.times[k]), Yv(v)); });
    ctx.stroke();
    let failures = 0;
    ctx.strokeStyle = '#c0152f';
    r.failed?.forEach((ok, k) => {
      if (ok) return;
      failures++;
      ctx.beginPath();
      ctx.moveTo(X(r.times[k]), i * h + h - 2);
      ctx.lineTo(X(r.times[k]), i * h + h - 8);
      ctx.stroke();
    });
    ctx.fillStyle = '#333';
    ctx.fillText(`${r.label}: ${vlo.toPrecision(3)} .. ${vhi.toPrecision(3)}` +
      (failures ? ` (not converged: ${failures} mark${failures > 1 ? 's' : ''})` : ''), 6, i * h + 11);
  });
  ctx.strokeStyle = '#c0152f';
  ctx.beginPath();
  ctx.moveTo(X(now), 0);
  ctx.lineTo(X(now), H);
  ctx.stroke();
  canvas.onclick = (e) => {  // jump to the frame nearest the time clicked
    const t = t0 + (e.offsetX - 4) / (W - 8) * (t1 - t0);
    let best = 0;
    data.time.forEach((tk, k) => { if (Math.abs(tk - t) < Math.abs(data.time[best] - t)) best = k; });
    setFrame(best);
  };
}

// -- time: slider, play -----------------------------------------------------------------------
$('slider').max = String(nf - 1);
$('slider').addEventListener('input', () => setFrame(Number($('slider').value)));
let playing = null;
function play() {
  if (playing) { clearInterval(playing); playing = null; $('play').innerHTML = '&#9654;'; return; }
  if (frame === nf - 1) setFrame(0);
  $('play').innerHTML = '&#10074;&#10074;';
  playing = setInterval(() => { if (frame >= nf - 1) play(); else setFrame(frame + 1); }, 50);
}
$('play').addEventListener('click', play);
document.addEventListener('keydown', (e) => {
  if (e.target.tagName === 'SELECT') return;
  if (e.key === ' ') { e.preventDefault(); play(); }
  if (e.key === 'ArrowRight') setFrame(frame + 1);
  if (e.key === 'ArrowLeft') setFrame(frame - 1);
});
for (const id of ['colour-by', 'show-contacts', 'show-mechanism', 'show-water']) {
  $(id).addEventListener('change', () => setFrame(frame));
}
$('show-edges').addEventListener('change', () => {
  for (const m of meshes) m.children[0].visible = $('show-edges').checked;
  render();
});

function render() { renderer.render(scene, camera); }
function resize() {
  const w = host.clientWidth || 800, h = host.clientHeight || 500;
  renderer.setSize(w, h);
  camera.aspect = w / h;
  camera.updateProjectionMatrix();
  render();
}
window.addEventListener('resize', resize);
resize();
lookFrom(dim === 3 ? 'iso' : '+z');
setFrame(0);

// #frame=K (from 0; -1: the last) opens the page at output frame K of those shown, and
// #colour=MODE coloured so (displacement, group, damage, stress); both: #frame=K&colour=MODE
const asked = /frame=(-?\d+)/.exec(location.hash), colour = /colour=(\w+)/.exec(location.hash);
if (colour && modes[colour[1]]) $('colour-by').value = colour[1];
if (asked || colour) setFrame(asked ? (Number(asked[1]) < 0 ? nf + Number(asked[1]) : Number(asked[1])) : frame);

// -- self test (page opened with #selftest): the browser test reads its report ----------------
window.saxumViewer = { setFrame, meshes, nb, nf };
if (location.hash.includes('selftest')) {
  const positions = () => meshes.map((m) => m.position.toArray().concat(m.quaternion.toArray()));
  const first = positions();
  $('slider').value = String(nf - 1);
  $('slider').dispatchEvent(new Event('input'));
  const last = positions();
  let blockMeshes = 0;
  scene.traverse((o) => { if (o.isMesh && o.userData.body !== undefined) blockMeshes++; });
  const movedBlocks = first.filter((p, b) => p.some((v, i) => Math.abs(v - last[b][i]) > 1e-9)).length;
  const report = { blocks: nb, frames: nf, blockMeshes, movedBlocks, frame, last,
    notes: notes.map((n) => n[1]),
    errors: errors.slice(), webgl: !!renderer.getContext() };
  const pre = document.createElement('pre');
  pre.id = 'saxum-selftest';
  pre.style.display = 'none';
  pre.textContent = JSON.stringify(report);
  document.body.appendChild(pre);
}
