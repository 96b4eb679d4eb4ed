// stridemap report page: the interactive 3D view of a run's map.
// The page embeds three.js and its OrbitControls as text; they are loaded
// from blob URLs, so the page works from a file with no network. Map layers
// arrive as base64 little-endian arrays (report_page.cpp). Every failure
// ends in a readable message in #view-message, never a blank view; the
// browser test reads document.body.dataset.view ("ready" or "error").
// Performance marks (measured from navigation, docs/performance.md):
// stridemap-data-read, stridemap-three-loaded, stridemap-mesh-built,
// stridemap-render-issued (the first render's calls made), and
// stridemap-first-frame (the frame after it reached the screen).

const messageBox = document.getElementById('view-message');

function showMessage(text) {
  messageBox.textContent = text;
  messageBox.hidden = false;
  document.getElementById('stage').hidden = true;
  document.body.dataset.view = 'error';
}

function moduleUrl(source) {
  return URL.createObjectURL(new Blob([source], { type: 'text/javascript' }));
}

async function loadThree() {
  const threeUrl = moduleUrl(document.getElementById('three-module').textContent);
  const orbitSource = document.getElementById('orbit-module').textContent.replace(/from\s*['"]three['"]/g, `from '${threeUrl}'`);
  const THREE = await import(threeUrl);
  const { OrbitControls } = await import(moduleUrl(orbitSource));
  return { THREE, OrbitControls };
}

// ---- data -----------------------------------------------------------------

function bytesOf(base64, what) {
  let binary;
  try {
    binary = atob(base64);
  } catch (e) {
    throw new Error(`${what}: the embedded data is not valid base64 (the page was cut or edited)`);
  }
  const bytes = new Uint8Array(binary.length);
  for (let k = 0; k < binary.length; ++k) bytes[k] = binary.charCodeAt(k);
  return bytes;
}

function halfToFloat(h) {
  const sign = h & 0x8000 ? -1 : 1;
  const exponent = (h >> 10) & 0x1f;
  const fraction = h & 0x3ff;
  if (exponent === 0) return sign * fraction * 2 ** -24;
  if (exponent === 31) return fraction ? NaN : sign * Infinity;
  return sign * (1 + fraction / 1024) * 2 ** (exponent - 15);
}

const bytesPerCell = { f32: 4, f16: 2, u16: 2, u8: 1 };

// Layers come deflated (zlib format, report_page.cpp); the browser's own
// DecompressionStream unpacks them. Uncompressed layers are read as well.
async function unpacked(bytes, compression, what) {
  if (!compression) return bytes;
  if (compression !== 'deflate') throw new Error(`${what}: unknown compression '${compression}'`);
  try {
    const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream('deflate'));
    return new Uint8Array(await new Response(stream).arrayBuffer());
  } catch (e) {
    throw new Error(`${what}: the embedded data cannot be unpacked (${e.message}); the page was cut or edited`);
  }
}

async function decodeLayer(layer, cells, mapName) {
  const what = `map '${mapName}', layer '${layer.name}'`;
  const size = bytesPerCell[layer.encoding];
  if (!size) throw new Error(`${what}: unknown encoding '${layer.encoding}'`);
  const bytes = await unpacked(bytesOf(layer.data ?? '', what), layer.compression, what);
  if (bytes.length !== cells * size) {
    throw new Error(`${what}: ${bytes.length} bytes where ${cells} cells need ${cells * size}`);
  }
  if (layer.encoding === 'f32') return new Float32Array(bytes.buffer);
  const out = new Float32Array(cells);
  if (layer.encoding === 'f16') {
    const halves = new Uint16Array(bytes.buffer);
    for (let k = 0; k < cells; ++k) out[k] = halfToFloat(halves[k]);
  } else if (layer.encoding === 'u16') {
    out.set(new Uint16Array(bytes.buffer));
  } else {
    out.set(bytes);
  }
  return out;
}

async function readMap(raw, index) {
  const name = raw?.name ?? `map ${index + 1}`;
  const rows = raw?.rows, cols = raw?.cols, cell = raw?.cell_size_m;
  if (!Number.isInteger(rows) || !Number.isInteger(cols) || rows < 2 || cols < 2) {
    throw new Error(`map '${name}': needs at least 2 x 2 cells, has ${rows} x ${cols}`);
  }
  if (!(cell > 0)) throw new Error(`map '${name}': cell size ${cell} is not positive`);
  const cells = rows * cols;
  const layers = new Map();
  for (const layer of raw.layers ?? []) layers.set(layer.name, { units: layer.units ?? '', values: await decodeLayer(layer, cells, name) });
  if (!layers.has('elevation')) throw new Error(`map '${name}': has no elevation layer`);
  const elevation = layers.get('elevation').values;
  if (raw.truth) {
    const truth = await decodeLayer(raw.truth, cells, name);
    const error = new Float32Array(cells);
    for (let k = 0; k < cells; ++k) error[k] = elevation[k] - truth[k];
    layers.set('error vs truth', { units: 'm', values: error, signed: true });
    raw.truthValues = truth;
  }
  let known = 0;
  for (let k = 0; k < cells; ++k) known += Number.isFinite(elevation[k]);
  if (known === 0) throw new Error(`map '${name}': holds no known cell, so there is nothing to draw (was anything mapped?)`);
  return { name, rows, cols, cell, ox: raw.origin_x_m ?? 0, oy: raw.origin_y_m ?? 0, layers, elevation, known,
           path: raw.path ?? [], lastPose: raw.last_pose ?? null, mount: raw.mount ?? null, truth: raw.truthValues ?? null };
}

async function readData() {
  const block = document.getElementById('stridemap-data');
  let data;
  try {
    data = JSON.parse(block.textContent);
  } catch (e) {
    throw new Error(`The page's map data is damaged (${e.message}); make the report again with 'stridemap report'.`);
  }
  for (const note of data.messages ?? []) {
    const p = document.createElement('p');
    p.className = 'message';
    p.textContent = note;
    document.getElementById('view').insertBefore(p, messageBox);
  }
  if (!Array.isArray(data.maps) || data.maps.length === 0) {
    throw new Error('This run left no readable map file (map.smap), so there is no 3D view; the tables and pictures below still show the run.');
  }
  const maps = await Promise.all(data.maps.map(readMap));
  // The run's truth, shown beside the map as a map of its own.
  if (maps[0].truth) {
    const m = maps[0];
    const layers = new Map([['elevation', { units: 'm', values: m.truth }]]);
    maps.push({ ...m, name: 'ground truth (simulated)', layers, elevation: m.truth, path: [], lastPose: null, truth: null });
  }
  return maps;
}

// ---- colours --------------------------------------------------------------

// Anchor colours of the scales, interpolated linearly (sRGB 0-1).
const scales = {
  viridis: [[0.267, 0.005, 0.329], [0.283, 0.141, 0.458], [0.254, 0.265, 0.530], [0.207, 0.372, 0.553],
            [0.164, 0.471, 0.558], [0.128, 0.567, 0.551], [0.135, 0.659, 0.518], [0.267, 0.749, 0.441],
            [0.478, 0.821, 0.318], [0.741, 0.873, 0.150], [0.993, 0.906, 0.144]],
  // Blue - white - red, for signed values centred on zero.
  diverging: [[0.130, 0.300, 0.650], [0.400, 0.600, 0.850], [0.970, 0.970, 0.970], [0.900, 0.480, 0.380], [0.700, 0.090, 0.120]],
};
const unknownColour = [0.55, 0.55, 0.55];

function colourAt(scale, t) {
  const anchors = scales[scale];
  const x = Math.min(Math.max(t, 0), 1) * (anchors.length - 1);
  const k = Math.min(Math.floor(x), anchors.length - 2), f = x - k;
  return [0, 1, 2].map((c) => anchors[k][c] * (1 - f) + anchors[k + 1][c] * f);
}

function percentile(sorted, p) {
  if (sorted.length === 0) return NaN;
  return sorted[Math.min(sorted.length - 1, Math.max(0, Math.round(p * (sorted.length - 1))))];
}

// 2nd to 98th percentile, so that a few outlier cells do not wash the map
// into one colour; signed layers get a range symmetric about zero.
function robustRange(layer) {
  const finite = Array.from(layer.values).filter(Number.isFinite);
  if (layer.signed) {
    const magnitudes = Float32Array.from(finite, Math.abs).sort();
    const m = percentile(magnitudes, 0.98) || 0.01;
    return [-m, m];
  }
  const sorted = Float32Array.from(finite).sort();
  let low = percentile(sorted, 0.02), high = percentile(sorted, 0.98);
  if (!(high > low)) { low = (low || 0) - 0.01; high = low + 0.02; }
  return [low, high];
}

function niceStep(span) {
  const raw = span / 4, magnitude = 10 ** Math.floor(Math.log10(raw)), n = raw / magnitude;
  return magnitude * (n < 1.5 ? 1 : n < 3 ? 2 : n < 7 ? 5 : 10);
}

function formatLength(m) { return m < 1 ? `${+(m * 1000).toPrecision(3)} mm` : `${+m.toPrecision(3)} m`; }

// ---- scene ----------------------------------------------------------------

function buildSurface(THREE, map, exaggeration) {
  const { rows, cols, cell, ox, oy, elevation } = map;
  const positions = new Float32Array(rows * cols * 3);
  for (let i = 0; i < rows; ++i) {
    for (let j = 0; j < cols; ++j) {
      const k = i * cols + j, z = elevation[k];
      positions.set([ox + i * cell, oy + j * cell, Number.isFinite(z) ? z * exaggeration : 0], 3 * k);
    }
  }
  // A triangle only where all its corners are known: unknown cells are holes.
  const index = [];
  const known = (k) => Number.isFinite(elevation[k]);
  for (let i = 0; i + 1 < rows; ++i) {
    for (let j = 0; j + 1 < cols; ++j) {
      const a = i * cols + j, b = a + cols, c = b + 1, d = a + 1;
      const ka = known(a), kb = known(b), kc = known(c), kd = known(d);
      if (ka && kb && kc) index.push(a, b, c);
      if (ka && kc && kd) index.push(a, c, d);
      if (!kc && ka && kb && kd) index.push(a, b, d);
      if (!ka && kb && kc && kd) index.push(b, c, d);
    }
  }
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  geometry.setAttribute('color', new THREE.BufferAttribute(new Float32Array(rows * cols * 3), 3));
  geometry.setIndex(index);
  geometry.computeVertexNormals();
  const mesh = new THREE.Mesh(geometry, new THREE.MeshLambertMaterial({ vertexColors: true, side: THREE.DoubleSide }));
  return mesh;
}

function paint(mesh, values, range, scale) {
  const colours = mesh.geometry.getAttribute('color');
  const [low, high] = range;
  for (let k = 0; k < values.length; ++k) {
    const v = values[k];
    colours.array.set(Number.isFinite(v) ? colourAt(scale, (v - low) / (high - low)) : unknownColour, 3 * k);
  }
  colours.needsUpdate = true;
}

function heightAt(map, x, y, exaggeration) {
  const i = Math.round((x - map.ox) / map.cell), j = Math.round((y - map.oy) / map.cell);
  if (i < 0 || j < 0 || i >= map.rows || j >= map.cols) return 0;
  const z = map.elevation[i * map.cols + j];
  return Number.isFinite(z) ? z * exaggeration : 0;
}

// The path, its start (a green ball) and heading (an arrow at its end), the
// last pose, and the sensor's footprint: where the scan plane meets the
// ground under the robot at the last pose.
function buildMarks(THREE, map, exaggeration, size) {
  const group = new THREE.Group();
  const lift = 0.01 * size;
  const point = (x, y) => new THREE.Vector3(x, y, heightAt(map, x, y, exaggeration) + lift);
  if (map.path.length >= 2) {
    const points = map.path.map(([x, y]) => point(x, y));
    group.add(new THREE.Line(new THREE.BufferGeometry().setFromPoints(points), new THREE.LineBasicMaterial({ color: 0xd62728 })));
    const start = new THREE.Mesh(new THREE.SphereGeometry(0.015 * size), new THREE.MeshBasicMaterial({ color: 0x2ca02c }));
    start.position.copy(points[0]);
    group.add(start);
    const n = points.length, heading = points[n - 1].clone().sub(points[Math.max(0, n - 4)]).setZ(0);
    if (heading.length() > 0) group.add(new THREE.ArrowHelper(heading.normalize(), points[n - 1], 0.08 * size, 0xd62728));
  }
  const pose = map.lastPose;
  if (pose) {
    const direction = new THREE.Vector3(Math.cos(pose.yaw_rad), Math.sin(pose.yaw_rad), 0);
    const at = point(pose.x_m, pose.y_m);
    group.add(new THREE.ArrowHelper(direction, at, 0.08 * size, 0xff7f0e));
    const m = map.mount;
    if (m && m.pitch_rad > 0.01) {
      const yaw = pose.yaw_rad + (m.yaw_rad ?? 0), c = Math.cos(yaw), s = Math.sin(yaw);
      const sx = pose.x_m + c * m.forward_offset_m - s * m.lateral_offset_m;
      const sy = pose.y_m + s * m.forward_offset_m + c * m.lateral_offset_m;
      const ahead = m.height_m / Math.tan(m.pitch_rad), half = m.height_m * Math.tan(Math.PI / 3) / Math.sin(m.pitch_rad);
      const ends = [-half, half].map((side) => new THREE.Vector3(sx + c * ahead - s * side, sy + s * ahead + c * side, at.z));
      group.add(new THREE.Line(new THREE.BufferGeometry().setFromPoints(ends), new THREE.LineBasicMaterial({ color: 0xff7f0e })));
    }
  }
  return group;
}

// Axes (x red, y green, z blue) and a white scale bar of a round length at
// the map's corner.
function buildScale(THREE, map, length) {
  const group = new THREE.Group();
  const corner = new THREE.Vector3(map.ox - map.cell, map.oy - map.cell, 0);
  group.add(new THREE.ArrowHelper(new THREE.Vector3(1, 0, 0), corner, length, 0xd62728));
  group.add(new THREE.ArrowHelper(new THREE.Vector3(0, 1, 0), corner, length, 0x2ca02c));
  group.add(new THREE.ArrowHelper(new THREE.Vector3(0, 0, 1), corner, length, 0x1f77b4));
  const bar = new THREE.Mesh(new THREE.BoxGeometry(length, map.cell * 1.5, map.cell * 0.5), new THREE.MeshBasicMaterial({ color: 0xffffff }));
  bar.position.set(map.ox + 0.5 * length, map.oy - 3 * map.cell, 0);
  group.add(bar);
  return group;
}

// ---- page -----------------------------------------------------------------

function control(html) {
  const span = document.createElement('span');
  span.innerHTML = html;
  document.getElementById('controls').appendChild(span);
  return span;
}

function drawLegend(state, range, layerName, units, scale, scaleLength) {
  const legend = document.getElementById('legend');
  const bar = document.createElement('canvas');
  bar.width = 220; bar.height = 14;
  const g = bar.getContext('2d');
  for (let x = 0; x < bar.width; ++x) {
    const [r, gr, b] = colourAt(scale, x / (bar.width - 1));
    g.fillStyle = `rgb(${255 * r},${255 * gr},${255 * b})`;
    g.fillRect(x, 0, 1, bar.height);
  }
  const digits = Math.max(0, -Math.floor(Math.log10(niceStep(range[1] - range[0]))) + 1);
  const unitText = units ? ` [${units}]` : '';
  legend.replaceChildren();
  const title = document.createElement('div');
  title.textContent = `${layerName}${unitText}${state.signed ? ': blue too low, white right, red too high' : ''}`;
  const ticks = document.createElement('div');
  ticks.className = 'ticks';
  ticks.innerHTML = `<span>${range[0].toFixed(digits)}</span><span>${((range[0] + range[1]) / 2).toFixed(digits)}</span><span>${range[1].toFixed(digits)}</span>`;
  const notes = document.createElement('div');
  notes.className = 'legend-notes';
  notes.innerHTML = `<span class="swatch hole"></span> hole = unknown cell &nbsp; <span class="swatch grey"></span> no value in this layer<br>` +
    `white bar and axes: ${formatLength(scaleLength)}; x red (forward), y green (left), z blue (up)<br>` +
    `<span class="swatch path"></span> path, green ball = start, arrow = heading &nbsp; <span class="swatch pose"></span> last pose and sensor footprint`;
  legend.append(title, bar, ticks, notes);
}

async function main() {
  let maps;
  try {
    maps = await readData();
    performance.mark('stridemap-data-read');
  } catch (e) {
    showMessage(e.message);
    return;
  }
  let THREE, OrbitControls;
  try {
    ({ THREE, OrbitControls } = await loadThree());
    performance.mark('stridemap-three-loaded');
  } catch (e) {
    showMessage(`The 3D library could not be loaded (${e.message}).`);
    return;
  }
  const canvas = document.getElementById('canvas3d');
  let renderer;
  try {
    renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
  } catch (e) {
    showMessage(`This browser cannot draw the 3D view (WebGL: ${e.message}); the tables and pictures below still show the run.`);
    return;
  }
  messageBox.hidden = true;
  const main = maps[0];
  const size = Math.hypot(main.rows, main.cols) * main.cell;
  const scaleLength = niceStep(Math.max(main.rows, main.cols) * main.cell);
  const state = { layer: 'elevation', exaggeration: 1, sideBySide: maps.length > 1, second: 1, range: null, signed: false };

  const views = maps.map((map) => {
    const scene = new THREE.Scene();
    scene.background = new THREE.Color(0xf4f4f4);
    scene.add(new THREE.HemisphereLight(0xffffff, 0x666666, 2.2));
    const sun = new THREE.DirectionalLight(0xffffff, 1.6);
    sun.position.set(-0.4, -0.6, 1.0);
    scene.add(sun);
    return { map, scene, mesh: null, marks: null };
  });
  const rebuild = () => {
    for (const view of views) {
      for (const old of [view.mesh, view.marks]) if (old) view.scene.remove(old);
      view.mesh = buildSurface(THREE, view.map, state.exaggeration);
      view.marks = buildMarks(THREE, view.map, state.exaggeration, size);
      view.scene.add(view.mesh, view.marks, buildScale(THREE, view.map, scaleLength));
    }
  };

  const layerNames = [...main.layers.keys()];
  const layerSelect = control(`<label>colour by <select id="layer">${layerNames.map((n) => `<option>${n}</option>`).join('')}</select></label>`).querySelector('select');
  const minInput = control('<label>from <input id="range-min" type="number" step="any" size="7"></label>').querySelector('input');
  const maxInput = control('<label>to <input id="range-max" type="number" step="any" size="7"></label>').querySelector('input');
  const autoButton = control('<button id="range-auto" type="button" title="2nd to 98th percentile">robust range</button>').querySelector('button');
  const exaggerationSelect = control('<label>heights x <select id="exaggeration"><option>1</option><option>2</option><option>5</option><option>10</option></select></label>').querySelector('select');
  let secondSelect = null, sideBox = null;
  if (maps.length > 1) {
    sideBox = control('<label><input id="side-by-side" type="checkbox" checked> side by side with</label>').querySelector('input');
    secondSelect = control(`<select id="second">${maps.slice(1).map((m, k) => `<option value="${k + 1}">${m.name}</option>`).join('')}</select>`).querySelector('select');
  }

  const camera = new THREE.PerspectiveCamera(35, 1, size / 1000, size * 20);
  camera.up.set(0, 0, 1);
  const target = new THREE.Vector3(main.ox + 0.5 * (main.rows - 1) * main.cell, main.oy + 0.5 * (main.cols - 1) * main.cell, 0);
  camera.position.set(target.x - 0.9 * size, target.y - 0.55 * size, 0.8 * size);
  const controls = new OrbitControls(camera, canvas);
  controls.target.copy(target);
  controls.screenSpacePanning = true;

  const render = () => {
    const width = canvas.clientWidth, height = canvas.clientHeight;
    if (canvas.width !== Math.floor(width * devicePixelRatio) || canvas.height !== Math.floor(height * devicePixelRatio)) {
      renderer.setPixelRatio(devicePixelRatio);
      renderer.setSize(width, height, false);
    }
    const split = state.sideBySide && views.length > 1;
    const shown = split ? [views[0], views[state.second]] : [views[0]];
    const w = width / shown.length;
    camera.aspect = w / height;
    camera.updateProjectionMatrix();
    renderer.setScissorTest(true);
    shown.forEach((view, k) => {
      renderer.setViewport(k * w, 0, w, height);
      renderer.setScissor(k * w, 0, w, height);
      renderer.render(view.scene, camera);
    });
    document.getElementById('stage').dataset.split = split ? 'yes' : 'no';
  };
  const recolour = (keepRange) => {
    const layer = main.layers.get(state.layer);
    state.signed = !!layer.signed;
    if (!keepRange) state.range = robustRange(layer);
    const scale = state.signed ? 'diverging' : 'viridis';
    for (const view of views) {
      // A map without this layer (the truth has no certainty) is drawn grey.
      const own = view.map.layers.get(state.layer)?.values ?? new Float32Array(view.map.elevation.length).fill(NaN);
      paint(view.mesh, own, state.range, scale);
    }
    minInput.value = +state.range[0].toPrecision(4);
    maxInput.value = +state.range[1].toPrecision(4);
    drawLegend(state, state.range, state.layer, layer.units, scale, scaleLength);
    render();
    document.body.dataset.layer = state.layer;
  };

  layerSelect.addEventListener('change', () => { state.layer = layerSelect.value; recolour(false); });
  const typedRange = () => {
    const low = parseFloat(minInput.value), high = parseFloat(maxInput.value);
    if (Number.isFinite(low) && Number.isFinite(high) && high > low) { state.range = [low, high]; recolour(true); }
  };
  minInput.addEventListener('change', typedRange);
  maxInput.addEventListener('change', typedRange);
  autoButton.addEventListener('click', () => recolour(false));
  exaggerationSelect.addEventListener('change', () => { state.exaggeration = +exaggerationSelect.value; rebuild(); recolour(true); });
  if (sideBox) {
    sideBox.addEventListener('change', () => { state.sideBySide = sideBox.checked; render(); });
    secondSelect.addEventListener('change', () => { state.second = +secondSelect.value; render(); });
  }
  controls.addEventListener('change', render);
  window.addEventListener('resize', render);
  rebuild();
  performance.mark('stridemap-mesh-built');
  recolour(false);
  performance.mark('stridemap-render-issued');
  document.body.dataset.readyMs = Math.round(performance.now());
  document.body.dataset.view = 'ready';
  // Two frames on: the first render's frame has been composited.
  requestAnimationFrame(() => requestAnimationFrame(() => {
    performance.mark('stridemap-first-frame');
    document.body.dataset.firstFrameMs = Math.round(performance.now());
  }));
}

main().catch((e) => showMessage(`The 3D view failed: ${e.message}`));
