// stridemap report page: the interactive 3D view of a run's map.
// The page embeds three.js and its OrbitControls as text; they are loaded
// from blob URLs, so the page works from a file with no network. Map layers
// arrive as base64 little-endian arrays (report_page.cpp). Every failure
// ends in a readable message in #view-message, never a blank view; the
// browser test reads document.body.dataset.view ("ready" or "error").
// Performance marks (measured from navigation, docs/performance.md):
// stridemap-script-start (the HTML parsed, this script running),
// stridemap-data-read, stridemap-three-loaded (and the data read),
// stridemap-context-made (three.js's renderer and its WebGL context),
// stridemap-mesh-built (the coarse level), stridemap-render-issued (the
// first render's calls made), stridemap-first-frame (the frame after it
// reached the screen) and stridemap-full-frame (the same for the full
// level; body.dataset.detail is then "full").

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

// Native base64 (Uint8Array.fromBase64) where the browser has it: a
// character loop over a megabyte of text was a visible part of the opening.
function bytesOf(base64, what) {
  try {
    if (Uint8Array.fromBase64) return Uint8Array.fromBase64(base64);
    const binary = atob(base64);
    const bytes = new Uint8Array(binary.length);
    for (let k = 0; k < binary.length; ++k) bytes[k] = binary.charCodeAt(k);
    return bytes;
  } catch (e) {
    throw new Error(`${what}: the embedded data is not valid base64 (the page was cut or edited)`);
  }
}

function halfToFloat(h) {
  const sign = h & 0x8000 ? -1 : 1;
  const exponent = (h >> 10) & 0x1f;
  const fraction = h & 0x3ff;
  if (exponent === 0) return sign * fraction * 2 ** -24;
  if (exponent === 31) return fraction ? NaN : sign * Infinity;
  return sign * (1 + fraction / 1024) * 2 ** (exponent - 15);
}

// Browsers without Float16Array get a table of all 65536 halves, made once,
// instead of a function call per cell.
let halfTable = null;
function halvesToFloats(halves) {
  if (typeof Float16Array !== 'undefined') return Float32Array.from(new Float16Array(halves.buffer, halves.byteOffset, halves.length));
  if (!halfTable) {
    halfTable = new Float32Array(65536);
    for (let h = 0; h < 65536; ++h) halfTable[h] = halfToFloat(h);
  }
  const out = new Float32Array(halves.length);
  for (let k = 0; k < halves.length; ++k) out[k] = halfTable[halves[k]];
  return out;
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
  // A fresh buffer: the typed views below need their byte offset aligned.
  const aligned = bytes.byteOffset % size === 0 ? bytes : bytes.slice();
  if (layer.encoding === 'f32') return new Float32Array(aligned.buffer, aligned.byteOffset, cells);
  if (layer.encoding === 'f16') return halvesToFloats(new Uint16Array(aligned.buffer, aligned.byteOffset, cells));
  if (layer.encoding === 'u16') return Float32Array.from(new Uint16Array(aligned.buffer, aligned.byteOffset, cells));
  return Float32Array.from(aligned);
}

async function readMap(raw, index) {
  const name = raw?.name ?? `map ${index + 1}`;
  const rows = raw?.rows, cols = raw?.cols, cell = raw?.cell_size_m;
  if (!Number.isInteger(rows) || !Number.isInteger(cols) || rows < 2 || cols < 2) {
    throw new Error(`map '${name}': needs at least 2 x 2 cells, has ${rows} x ${cols}`);
  }
  if (!(cell > 0)) throw new Error(`map '${name}': cell size ${cell} is not positive`);
  const cells = rows * cols;
  // The first frame needs the elevation (and the truth) only; the other
  // layers (a dozen on a mapped run) unpack after it (loadLayers).
  const rawLayers = raw.layers ?? [];
  const rawElevation = rawLayers.find((layer) => layer.name === 'elevation');
  if (!rawElevation) throw new Error(`map '${name}': has no elevation layer`);
  const [elevation, truth] = await Promise.all([decodeLayer(rawElevation, cells, name),
                                                raw.truth ? decodeLayer(raw.truth, cells, name) : null]);
  const layers = new Map(rawLayers.map((layer) => [layer.name, {
    units: layer.units ?? '',
    values: layer === rawElevation ? elevation : null,
    load: () => decodeLayer(layer, cells, name),
  }]));
  if (truth) {
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

// Unpacks the layers readMap left for later (all at once: DecompressionStream
// works beside the script).
function loadLayers(maps) {
  const pending = [];
  for (const map of maps) {
    for (const layer of map.layers.values()) {
      if (layer.values || !layer.load) continue;
      layer.loading ??= layer.load().then((values) => { layer.values = values; });
      pending.push(layer.loading);
    }
  }
  return Promise.all(pending);
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
  const values = layer.values, finite = new Float32Array(values.length);
  let n = 0;
  for (let k = 0; k < values.length; ++k) {
    const v = values[k];
    if (Number.isFinite(v)) finite[n++] = layer.signed ? Math.abs(v) : v;
  }
  const sorted = finite.subarray(0, n).sort();
  if (layer.signed) {
    const m = percentile(sorted, 0.98) || 0.01;
    return [-m, m];
  }
  let low = percentile(sorted, 0.02), high = percentile(sorted, 0.98);
  if (!(high > low)) { low = (low || 0) - 0.01; high = low + 0.02; }
  return [low, high];
}

// Each scale as 256 colours of three bytes, made once: colouring a cell is
// then a table look-up, not an interpolation.
const colourTables = {};
function colourTable(scale) {
  if (!colourTables[scale]) {
    const table = new Uint8Array(256 * 3);
    for (let k = 0; k < 256; ++k) table.set(colourAt(scale, k / 255).map((c) => Math.round(255 * c)), 3 * k);
    colourTables[scale] = table;
  }
  return colourTables[scale];
}

function niceStep(span) {
  const raw = span / 4, magnitude = 10 ** Math.floor(Math.log10(raw)), n = raw / magnitude;
  return magnitude * (n < 1.5 ? 1 : n < 3 ? 2 : n < 7 ? 5 : 10);
}

function formatLength(m) { return m < 1 ? `${+(m * 1000).toPrecision(3)} mm` : `${+m.toPrecision(3)} m`; }

// ---- scene ----------------------------------------------------------------

// The coarse level drawn first has at most this many vertices a side; the
// full map (a vertex per cell) follows once the first frame is on screen.
// Software WebGL (no GPU) draws the half million triangles of a 500 x 500
// map in seconds, the coarse level in a fraction (docs/performance.md).
const coarseSide = 128;

// One level of detail of a map's surface: a vertex at every step-th row and
// column (and the last ones), so the outline stays. Its x, y and triangle
// index are made once; heights, normals and colours are rewritten in place
// when the exaggeration or the colour layer changes.
function buildLevel(THREE, map, step) {
  const pick = (n) => { const at = []; for (let k = 0; k < n - 1; k += step) at.push(k); at.push(n - 1); return at; };
  const rowsAt = pick(map.rows), colsAt = pick(map.cols);
  const nr = rowsAt.length, nc = colsAt.length, vertices = nr * nc;
  const cellOf = new Uint32Array(vertices), positions = new Float32Array(vertices * 3);
  for (let r = 0; r < nr; ++r) {
    for (let c = 0; c < nc; ++c) {
      const v = r * nc + c;
      cellOf[v] = rowsAt[r] * map.cols + colsAt[c];
      positions[3 * v] = map.ox + rowsAt[r] * map.cell;
      positions[3 * v + 1] = map.oy + colsAt[c] * map.cell;
    }
  }
  // A triangle only where all its corners are known: unknown cells are holes.
  const elevation = map.elevation;
  const known = (v) => Number.isFinite(elevation[cellOf[v]]);
  const index = new Uint32Array(6 * (nr - 1) * (nc - 1));
  let n = 0;
  const triangle = (a, b, c) => { index[n++] = a; index[n++] = b; index[n++] = c; };
  for (let r = 0; r + 1 < nr; ++r) {
    for (let c = 0; c + 1 < nc; ++c) {
      const a = r * nc + c, b = a + nc, cc = b + 1, d = a + 1;
      const ka = known(a), kb = known(b), kc = known(cc), kd = known(d);
      if (ka && kb && kc) triangle(a, b, cc);
      if (ka && kc && kd) triangle(a, cc, d);
      if (!kc && ka && kb && kd) triangle(a, b, d);
      if (!ka && kb && kc && kd) triangle(b, cc, d);
    }
  }
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  geometry.setAttribute('normal', new THREE.BufferAttribute(new Float32Array(vertices * 3), 3));
  geometry.setAttribute('color', new THREE.BufferAttribute(new Uint8Array(vertices * 3), 3, true));
  geometry.setIndex(new THREE.BufferAttribute(index.slice(0, n), 1));
  return { step, nr, nc, cellOf, geometry };
}

// Heights and normals for an exaggeration. Normals come from the heights of
// the grid neighbours (central differences, one-sided at holes and edges):
// the same surface as the triangles' own normals, without a pass over them.
function setHeights(level, map, exaggeration) {
  const { nr, nc, cellOf, geometry } = level;
  const positions = geometry.getAttribute('position'), normals = geometry.getAttribute('normal');
  const p = positions.array, out = normals.array, elevation = map.elevation;
  const z = new Float32Array(nr * nc);
  for (let v = 0; v < z.length; ++v) {
    const h = elevation[cellOf[v]] * exaggeration;
    z[v] = h;
    p[3 * v + 2] = Number.isFinite(h) ? h : 0;
  }
  // Slope along one grid direction at v: neighbours at v - stride and
  // v + stride when they exist (has*) and are known.
  const slope = (v, stride, hasBefore, hasAfter, axis) => {
    const before = hasBefore && Number.isFinite(z[v - stride]) ? v - stride : v;
    const after = hasAfter && Number.isFinite(z[v + stride]) ? v + stride : v;
    return after === before ? 0 : (z[after] - z[before]) / (p[3 * after + axis] - p[3 * before + axis]);
  };
  for (let r = 0; r < nr; ++r) {
    for (let c = 0; c < nc; ++c) {
      const v = r * nc + c;
      let nx = 0, ny = 0, nz = 1;
      if (Number.isFinite(z[v])) {
        nx = -slope(v, nc, r > 0, r + 1 < nr, 0);
        ny = -slope(v, 1, c > 0, c + 1 < nc, 1);
        const length = Math.hypot(nx, ny, 1);
        nx /= length; ny /= length; nz = 1 / length;
      }
      out[3 * v] = nx; out[3 * v + 1] = ny; out[3 * v + 2] = nz;
    }
  }
  positions.needsUpdate = true;
  normals.needsUpdate = true;
  geometry.boundingSphere = null;
  geometry.boundingBox = null;
}

function paint(level, values, range, scale) {
  const colours = level.geometry.getAttribute('color');
  const out = colours.array, table = colourTable(scale), cellOf = level.cellOf;
  const [low, high] = range, toIndex = 255 / (high - low);
  const grey = Math.round(255 * unknownColour[0]);
  for (let v = 0; v < cellOf.length; ++v) {
    const value = values[cellOf[v]];
    if (Number.isFinite(value)) {
      const t = 3 * Math.min(255, Math.max(0, Math.round((value - low) * toIndex)));
      out[3 * v] = table[t]; out[3 * v + 1] = table[t + 1]; out[3 * v + 2] = table[t + 2];
    } else {
      out[3 * v] = out[3 * v + 1] = out[3 * v + 2] = grey;
    }
  }
  colours.needsUpdate = true;
}

function heightAt(map, x, y, exaggeration) {
  const i = Math.round((x - map.ox) / map.cell), j = Math.round((y - map.oy) / map.cell);
  if (i < 0 || j < 0 || i >= map.rows || j >= map.cols) return 0;
  const z = map.elevation[i * map.cols + j];
  return Number.isFinite(z) ? z * exaggeration : 0;
}

// The map's rectangle on the ground, cell edges included.
function mapRectangle(map) {
  const half = 0.5 * map.cell;
  return { x0: map.ox - half, y0: map.oy - half, x1: map.ox + (map.rows - 0.5) * map.cell, y1: map.oy + (map.cols - 0.5) * map.cell };
}

// The part of the segment a-b inside the rectangle (Liang-Barsky), or null.
function clipSegment(a, b, rect) {
  const dx = b[0] - a[0], dy = b[1] - a[1];
  let t0 = 0, t1 = 1;
  for (const [p, q] of [[-dx, a[0] - rect.x0], [dx, rect.x1 - a[0]], [-dy, a[1] - rect.y0], [dy, rect.y1 - a[1]]]) {
    if (p === 0) {
      if (q < 0) return null;
    } else {
      const t = q / p;
      if (p < 0) t0 = Math.max(t0, t); else t1 = Math.min(t1, t);
    }
  }
  return t0 <= t1 ? [[a[0] + t0 * dx, a[1] + t0 * dy], [a[0] + t1 * dx, a[1] + t1 * dy]] : null;
}

// A polyline cut to the rectangle: the runs inside it, each at least two points.
function clipPolyline(points, rect) {
  const runs = [];
  let run = [];
  for (let k = 0; k + 1 < points.length; ++k) {
    const piece = clipSegment(points[k], points[k + 1], rect);
    if (!piece) {
      if (run.length >= 2) runs.push(run);
      run = [];
      continue;
    }
    const last = run[run.length - 1];
    if (!last || last[0] !== piece[0][0] || last[1] !== piece[0][1]) {
      if (run.length >= 2) runs.push(run);
      run = [piece[0]];
    }
    run.push(piece[1]);
  }
  if (run.length >= 2) runs.push(run);
  return runs;
}

// The path, its start (a green ball) and heading (an arrow at its end), the
// last pose, and the sensor's footprint: where the scan plane meets the
// ground under the robot at the last pose. A map of real data can be a
// window onto a longer walk, and a shallow pitch puts the footprint metres
// away: both are cut to the map's rectangle (or left out), so that they
// never stretch across the view or pull the camera away from the map.
function buildMarks(THREE, map, exaggeration, size) {
  const group = new THREE.Group();
  const lift = 0.01 * size;
  const rect = mapRectangle(map);
  const inside = (x, y) => x >= rect.x0 && x <= rect.x1 && y >= rect.y0 && y <= rect.y1;
  const point = (x, y) => new THREE.Vector3(x, y, heightAt(map, x, y, exaggeration) + lift);
  const pathMaterial = new THREE.LineBasicMaterial({ color: 0xd62728 });
  for (const run of clipPolyline(map.path, rect)) {
    group.add(new THREE.Line(new THREE.BufferGeometry().setFromPoints(run.map(([x, y]) => point(x, y))), pathMaterial));
  }
  if (map.path.length >= 2) {
    const first = map.path[0], n = map.path.length, end = map.path[n - 1], before = map.path[Math.max(0, n - 4)];
    if (inside(first[0], first[1])) {
      const start = new THREE.Mesh(new THREE.SphereGeometry(0.015 * size), new THREE.MeshBasicMaterial({ color: 0x2ca02c }));
      start.position.copy(point(first[0], first[1]));
      group.add(start);
    }
    const heading = new THREE.Vector3(end[0] - before[0], end[1] - before[1], 0);
    if (heading.length() > 0 && inside(end[0], end[1])) {
      group.add(new THREE.ArrowHelper(heading.normalize(), point(end[0], end[1]), 0.08 * size, 0xd62728));
    }
  }
  const pose = map.lastPose;
  if (pose && inside(pose.x_m, pose.y_m)) {
    const direction = new THREE.Vector3(Math.cos(pose.yaw_rad), Math.sin(pose.yaw_rad), 0);
    const at = point(pose.x_m, pose.y_m);
    group.add(new THREE.ArrowHelper(direction, at, 0.08 * size, 0xff7f0e));
    const m = map.mount;
    if (m && m.pitch_rad > 0.01) {
      const yaw = pose.yaw_rad + (m.yaw_rad ?? 0), c = Math.cos(yaw), s = Math.sin(yaw);
      const sx = pose.x_m + c * m.forward_offset_m - s * m.lateral_offset_m;
      const sy = pose.y_m + s * m.forward_offset_m + c * m.lateral_offset_m;
      const ahead = m.height_m / Math.tan(m.pitch_rad), half = m.height_m * Math.tan(Math.PI / 3) / Math.sin(m.pitch_rad);
      const ends = [-half, half].map((side) => [sx + c * ahead - s * side, sy + s * ahead + c * side]);
      const piece = clipSegment(ends[0], ends[1], rect);
      if (piece) {
        const line = piece.map(([x, y]) => new THREE.Vector3(x, y, at.z));
        group.add(new THREE.Line(new THREE.BufferGeometry().setFromPoints(line), new THREE.LineBasicMaterial({ color: 0xff7f0e })));
      }
    }
  }
  return group;
}

// The box of the known cells of every map (x, y, and heights at the
// exaggeration), which the camera frames.
function knownBox(maps, exaggeration) {
  const box = { min: [Infinity, Infinity, Infinity], max: [-Infinity, -Infinity, -Infinity] };
  for (const map of maps) {
    for (let i = 0; i < map.rows; ++i) {
      for (let j = 0; j < map.cols; ++j) {
        const z = map.elevation[i * map.cols + j];
        if (!Number.isFinite(z)) continue;
        const p = [map.ox + i * map.cell, map.oy + j * map.cell, z * exaggeration];
        for (let a = 0; a < 3; ++a) { box.min[a] = Math.min(box.min[a], p[a]); box.max[a] = Math.max(box.max[a], p[a]); }
      }
    }
  }
  // Cell edges, not centres, bound the drawn surface's outline.
  for (let a = 0; a < 2; ++a) { box.min[a] -= 0.5 * maps[0].cell; box.max[a] += 0.5 * maps[0].cell; }
  return box;
}

function boxCorners(box) {
  const corners = [];
  for (const x of [box.min[0], box.max[0]]) for (const y of [box.min[1], box.max[1]]) for (const z of [box.min[2], box.max[2]]) corners.push([x, y, z]);
  return corners;
}

// Moves the camera along its current line of sight (towards the target,
// which goes to the box's centre) until every corner of the box lies
// inside the picture with a margin: for a corner at offset p from the
// target, seen from distance d along the forward axis f, its image is
// inside when |p.right| <= (d + p.f) tan(horizontal half-angle), the same
// for up; the least d that meets all of them frames the box exactly.
function frameBox(THREE, camera, controls, box, margin = 0.9) {
  const centre = new THREE.Vector3((box.min[0] + box.max[0]) / 2, (box.min[1] + box.max[1]) / 2, (box.min[2] + box.max[2]) / 2);
  const forward = controls.target.clone().sub(camera.position).normalize();
  const right = new THREE.Vector3().crossVectors(forward, camera.up).normalize();
  const up = new THREE.Vector3().crossVectors(right, forward);
  const tanV = margin * Math.tan(THREE.MathUtils.degToRad(camera.fov / 2)), tanH = tanV * camera.aspect;
  let distance = 0, depth = 0;
  for (const c of boxCorners(box)) {
    const p = new THREE.Vector3(...c).sub(centre);
    const along = p.dot(forward);
    distance = Math.max(distance, Math.abs(p.dot(right)) / tanH - along, Math.abs(p.dot(up)) / tanV - along);
    depth = Math.max(depth, Math.abs(along));
  }
  distance = Math.max(distance, 1e-3);
  controls.target.copy(centre);
  camera.position.copy(centre).addScaledVector(forward, -distance);
  // Near enough for the user to zoom in close, far enough for the depth buffer.
  camera.near = distance / 2000;
  camera.far = 10 * (distance + depth);
  camera.updateProjectionMatrix();
  controls.update();
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
  // The colour bar is a CSS gradient through the scale's anchors (linear in
  // sRGB, as colourAt), not a 2D canvas: one canvas less for the GPU
  // process to set up before the first frame (docs/performance.md).
  const bar = document.createElement('div');
  bar.style.cssText = 'width: 220px; height: 14px';
  const anchors = scales[scale];
  const stops = anchors.map((rgb, k) => `rgb(${rgb.map((c) => Math.round(255 * c)).join(',')}) ${(100 * k / (anchors.length - 1)).toFixed(1)}%`);
  bar.style.background = `linear-gradient(to right, ${stops.join(', ')})`;
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
  const scaleBox = document.createElement('div');
  scaleBox.append(title, bar, ticks);
  legend.append(scaleBox, notes);
}

async function main() {
  performance.mark('stridemap-script-start');
  // three.js compiles while the data unpacks; a failure of either is
  // reported in its turn, never as an unhandled rejection.
  const three = loadThree().then((loaded) => ({ loaded }), (error) => ({ error }));
  let maps;
  try {
    maps = await readData();
    performance.mark('stridemap-data-read');
  } catch (e) {
    showMessage(e.message);
    return;
  }
  const { loaded, error } = await three;
  if (error) {
    showMessage(`The 3D library could not be loaded (${error.message}).`);
    return;
  }
  const { THREE, OrbitControls } = loaded;
  performance.mark('stridemap-three-loaded');
  const canvas = document.getElementById('canvas3d');
  let renderer;
  try {
    renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
  } catch (e) {
    showMessage(`This browser cannot draw the 3D view (WebGL: ${e.message}); the tables and pictures below still show the run.`);
    return;
  }
  performance.mark('stridemap-context-made');
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
    scene.add(buildScale(THREE, map, scaleLength));
    return { map, scene, levels: [], mesh: null, marks: null };
  });
  const material = new THREE.MeshLambertMaterial({ vertexColors: true, side: THREE.DoubleSide });
  const colourLevel = (view, level) => {
    // A map without this layer (the truth has no certainty) is drawn grey.
    const own = view.map.layers.get(state.layer)?.values ?? new Float32Array(view.map.elevation.length).fill(NaN);
    paint(level, own, state.range, state.signed ? 'diverging' : 'viridis');
  };
  // Shows a level (made now if new) of every view, in the current heights
  // and colours.
  const showLevel = (step) => {
    for (const view of views) {
      let level = view.levels.find((l) => l.step === step);
      if (!level) {
        level = buildLevel(THREE, view.map, step);
        setHeights(level, view.map, state.exaggeration);
        if (state.range) colourLevel(view, level);
        view.levels.push(level);
      }
      if (view.mesh) view.scene.remove(view.mesh);
      view.mesh = new THREE.Mesh(level.geometry, material);
      view.scene.add(view.mesh);
      // A coarser level is not shown again: no more repainting it.
      for (const old of view.levels) if (old.step > step) old.geometry.dispose();
      view.levels = view.levels.filter((l) => l.step <= step);
    }
  };
  const placeMarks = () => {
    for (const view of views) {
      if (view.marks) view.scene.remove(view.marks);
      view.marks = buildMarks(THREE, view.map, state.exaggeration, size);
      view.scene.add(view.marks);
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
  // Seen from behind the start (-x), a little from the right (-y) and above;
  // frameBox then sets the distance.
  const target = new THREE.Vector3(main.ox + 0.5 * (main.rows - 1) * main.cell, main.oy + 0.5 * (main.cols - 1) * main.cell, 0);
  camera.position.set(target.x - 0.9 * size, target.y - 0.55 * size, 0.8 * size);
  const controls = new OrbitControls(camera, canvas);
  controls.target.copy(target);
  controls.screenSpacePanning = true;
  // The camera frames the maps until the user moves it; a resize, the
  // split or a new exaggeration then frames them again.
  let userMoved = false;
  controls.addEventListener('start', () => { userMoved = true; });
  const shownViews = () => (state.sideBySide && views.length > 1 ? [views[0], views[state.second]] : [views[0]]);
  const aspectNow = () => (canvas.clientWidth / shownViews().length) / Math.max(1, canvas.clientHeight);
  // A canvas not laid out yet (a page still loading on a busy machine, a
  // hidden tab) has no width: framing for it would put the camera at
  // infinity, NaN from then on, and the view would stay blank. Such a
  // canvas is framed and drawn once it has a size (the observer below).
  const frame = () => {
    const aspect = aspectNow();
    if (!(aspect > 0 && Number.isFinite(aspect))) return;
    camera.aspect = aspect;
    frameBox(THREE, camera, controls, knownBox(shownViews().map((v) => v.map), state.exaggeration));
  };

  const render = () => {
    const width = canvas.clientWidth, height = canvas.clientHeight;
    if (!(width > 0 && height > 0)) return;
    if (canvas.width !== Math.floor(width * devicePixelRatio) || canvas.height !== Math.floor(height * devicePixelRatio)) {
      renderer.setPixelRatio(devicePixelRatio);
      renderer.setSize(width, height, false);
    }
    const shown = shownViews(), split = shown.length > 1;
    const w = width / shown.length;
    if (!userMoved && Math.abs(camera.aspect - w / height) > 1e-6) frame();
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
    for (const view of views) for (const level of view.levels) colourLevel(view, level);
    minInput.value = +state.range[0].toPrecision(4);
    maxInput.value = +state.range[1].toPrecision(4);
    drawLegend(state, state.range, state.layer, layer.units, scale, scaleLength);
    render();
    document.body.dataset.layer = state.layer;
  };

  layerSelect.addEventListener('change', async () => {
    state.layer = layerSelect.value;
    try {
      await loadLayers(maps);
    } catch (e) {
      showMessage(e.message);
      return;
    }
    if (state.layer === layerSelect.value) recolour(false);
  });
  const typedRange = () => {
    const low = parseFloat(minInput.value), high = parseFloat(maxInput.value);
    if (Number.isFinite(low) && Number.isFinite(high) && high > low) { state.range = [low, high]; recolour(true); }
  };
  minInput.addEventListener('change', typedRange);
  maxInput.addEventListener('change', typedRange);
  autoButton.addEventListener('click', () => recolour(false));
  exaggerationSelect.addEventListener('change', () => {
    state.exaggeration = +exaggerationSelect.value;
    for (const view of views) for (const level of view.levels) setHeights(level, view.map, state.exaggeration);
    placeMarks();
    if (!userMoved) frame();
    render();
  });
  if (sideBox) {
    sideBox.addEventListener('change', () => { state.sideBySide = sideBox.checked; render(); });
    secondSelect.addEventListener('change', () => { state.second = +secondSelect.value; if (!userMoved) frame(); render(); });
  }
  controls.addEventListener('change', render);
  window.addEventListener('resize', render);
  new ResizeObserver(() => render()).observe(canvas);
  // The coarse level first, so that the view is on screen quickly; the full
  // one after that frame, in a task of its own.
  const coarseStep = Math.max(1, Math.ceil(Math.max(main.rows, main.cols) / coarseSide));
  showLevel(coarseStep);
  placeMarks();
  frame();
  // For the browser test (tests/browser/report_page_test.mjs): where a
  // point of the world lands in a panel (normalised device coordinates,
  // -1 to 1 inside), the panels' size, and the box of view k's marks.
  window.stridemapView = {
    project: (x, y, z) => { const p = new THREE.Vector3(x, y, z).project(camera); return [p.x, p.y, p.z]; },
    panels: () => ({ count: shownViews().length, width: canvas.clientWidth / shownViews().length, height: canvas.clientHeight }),
    marksBox: (k = 0) => {
      const box = new THREE.Box3().setFromObject(views[k].marks);
      return box.isEmpty() ? null : { min: box.min.toArray(), max: box.max.toArray() };
    },
    heights: () => { const box = knownBox(shownViews().map((v) => v.map), state.exaggeration); return [box.min[2], box.max[2]]; },
    userMoved: () => userMoved,
  };
  performance.mark('stridemap-mesh-built');
  recolour(false);
  performance.mark('stridemap-render-issued');
  document.body.dataset.readyMs = Math.round(performance.now());
  document.body.dataset.view = 'ready';
  const fullShown = () => {
    performance.mark('stridemap-full-frame');
    document.body.dataset.detail = 'full';
  };
  // Two frames on: the render's frame has been composited.
  const afterNextFrame = (then) => requestAnimationFrame(() => requestAnimationFrame(then));
  afterNextFrame(() => {
    performance.mark('stridemap-first-frame');
    document.body.dataset.firstFrameMs = Math.round(performance.now());
    if (coarseStep === 1) {
      loadLayers(maps).then(fullShown, (e) => showMessage(e.message));
      return;
    }
    loadLayers(maps).then(() => {
      showLevel(1);
      render();
      afterNextFrame(fullShown);
    }, (e) => showMessage(e.message));
  });
}

main().catch((e) => showMessage(`The 3D view failed: ${e.message}`));
