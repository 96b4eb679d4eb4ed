// How long a report page takes to show its 3D view: a measurement tool, not
// a test (docs/performance.md, "The report page"). Opens each page several
// times in Debian's headless Chromium, each time in a fresh browser context,
// and prints the milliseconds from navigation start to the page's marks
// (web/report.js), the share of canvas pixels unlike the background at the
// first frame, the medians, and the machine's load average (the machine may
// be shared; the figures mean little without it).
//
// It also prints CPU time, which a loaded machine inflates far less than wall
// time: read from /proc (Linux) at the moment the page sets each mark (the
// tool wraps performance.mark and is called back through a binding), from
// just before navigation: the renderer's main thread, the renderer processes
// (all threads), the GPU process (SwiftShader rasterises there) and all of
// Chromium's processes. Chromium's own Performance.getMetrics (TaskDuration,
// ScriptDuration) can only be read after the fact, by a round trip to the
// busy renderer, so it would include the full surface's work; it is not used.
//
//   node tests/browser/page_open_time.mjs --modules build/web/node_modules \
//        [--tool build/bin/stridemap --scene scenes/cart_rail_boxes.yaml --seeds 1,2,3 --cells 500 --work DIR] \
//        [--page some/report.html ...] [--loads 5] [--chromium /usr/bin/chromium]
//
// With --tool, it first makes one page per seed (`experiment cart-rail
// --cells N --report`) in --work (a new folder it creates; an existing
// folder is refused, so it never writes over a user's files).
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import { createRequire } from 'node:module';
import os from 'node:os';
import path from 'node:path';

const argv = process.argv.slice(2);
const option = (name, fallback) => { const k = argv.indexOf(`--${name}`); return k >= 0 ? argv[k + 1] : fallback; };
const pages = argv.flatMap((a, k) => (a === '--page' ? [argv[k + 1]] : []));
const modules = option('modules');
const loads = Number(option('loads', '5'));
const chromiumPath = option('chromium', '/usr/bin/chromium');
if (!modules || !(loads >= 1)) {
  console.error('usage: page_open_time.mjs --modules NODE_MODULES [--tool STRIDEMAP --work DIR [--scene S] [--seeds 1,2,3] [--cells 500]] [--page FILE ...] [--loads 5]');
  process.exit(2);
}
if (!fs.existsSync(chromiumPath)) {
  console.error(`${chromiumPath} is missing: install Debian's chromium ('make deps')`);
  process.exit(2);
}

const tool = option('tool');
if (tool) {
  const work = option('work');
  if (!work) { console.error('--tool needs --work DIR (a folder that does not exist yet)'); process.exit(2); }
  if (fs.existsSync(work)) { console.error(`${work} exists; give a new folder (this tool never writes over files it did not make)`); process.exit(2); }
  const scene = option('scene', 'scenes/cart_rail_boxes.yaml'), cells = option('cells', '500');
  for (const seed of option('seeds', '1,2,3').split(',')) {
    const out = path.join(work, `seed${seed}`);
    execFileSync(tool, ['experiment', 'cart-rail', '--sensor', 'urg', '--scene', scene, '--cells', cells, '--out', out,
                        '--seed', seed, '--report', '--quiet'], { stdio: ['ignore', 'ignore', 'inherit'] });
    pages.push(path.join(out, 'cart-rail-urg', 'report.html'));
  }
}
if (pages.length === 0) { console.error('no page: give --page FILE or --tool to make pages'); process.exit(2); }

const { chromium } = createRequire(path.resolve(modules, 'x.js'))('playwright-core');
const browser = await chromium.launch({
  executablePath: chromiumPath,
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'],
});
const markNames = ['script-start', 'data-read', 'three-loaded', 'context-made', 'mesh-built', 'render-issued', 'first-frame', 'full-frame'];
const median = (values) => {
  const s = values.filter(Number.isFinite).sort((a, b) => a - b), h = s.length >> 1;
  return s.length === 0 ? NaN : s.length % 2 ? s[h] : (s[h - 1] + s[h]) / 2;
};
const fmt = (v) => (Number.isFinite(v) ? v.toFixed(0).padStart(6) : '     -');
const loadAverage = () => os.loadavg().map((v) => v.toFixed(2)).join(' ');

// CPU time [ms] of Chromium's processes (this process's descendants) by
// kind, from /proc/PID/stat utime + stime (clock ticks of 10 ms); NaN where
// there is no /proc.
const msPerTick = 10;
function cpuTimes() {
  const total = { main: 0, renderer: 0, gpu: 0, all: 0 };
  let entries;
  try { entries = fs.readdirSync('/proc').filter((d) => /^\d+$/.test(d)); } catch { return { main: NaN, renderer: NaN, gpu: NaN, all: NaN }; }
  const ticksOf = (file) => { const t = fs.readFileSync(file, 'utf8'), f = t.slice(t.lastIndexOf(')') + 2).split(' '); return { ppid: +f[1], ticks: +f[11] + +f[12] }; };
  const procs = [];
  for (const pid of entries) {
    try { procs.push({ pid: +pid, ...ticksOf(`/proc/${pid}/stat`) }); } catch { /* gone meanwhile */ }
  }
  const ours = new Set([process.pid]);
  for (let grew = true; grew;) {
    grew = false;
    for (const p of procs) if (!ours.has(p.pid) && ours.has(p.ppid)) { ours.add(p.pid); grew = true; }
  }
  for (const p of procs) {
    if (p.pid === process.pid || !ours.has(p.pid)) continue;
    let kind = '';
    try { kind = fs.readFileSync(`/proc/${p.pid}/cmdline`, 'utf8').match(/--type=([a-z-]+)/)?.[1] ?? ''; } catch { continue; }
    total.all += p.ticks * msPerTick;
    if (kind === 'gpu-process') total.gpu += p.ticks * msPerTick;
    if (kind === 'renderer') {
      total.renderer += p.ticks * msPerTick;
      try { total.main += ticksOf(`/proc/${p.pid}/task/${p.pid}/stat`).ticks * msPerTick; } catch { /* gone */ }
    }
  }
  return total;
}
const cpuKinds = ['main', 'renderer', 'gpu', 'all'];
const cpuLabel = { main: 'renderer main thread', renderer: 'renderer processes', gpu: 'GPU process', all: 'all of Chromium' };

console.log(`chromium ${browser.version()}, ${os.cpus().length} cores, load average before: ${loadAverage()}`);
console.log(`${'page: ms from navigation start'.padEnd(40)} ${'MB'.padStart(5)} ${markNames.map((n) => n.padStart(14)).join('')}  non-background`);
console.log(`${'  CPU ms to each mark: main thread'.padEnd(46)} ${markNames.map(() => ''.padStart(14)).join('')}  ` +
            `at first frame: ${cpuKinds.map((k) => k.padStart(9)).join('')}`);
// Round robin over the pages, so that a change in the machine's load hits
// all of them alike (pages made by two versions compare fairly).
const columns = [...markNames, ...markNames.map((n) => `cpu ${n}`), ...cpuKinds];
const all = Object.fromEntries(columns.map((n) => [n, []]));
const perPage = new Map(pages.map((file) => [file, Object.fromEntries(columns.map((n) => [n, []]))]));
try {
  // One opening first, not counted: the browser's first WebGL page also
  // starts its GPU process's SwiftShader.
  {
    const context = await browser.newContext({ viewport: { width: 1200, height: 900 } });
    const page = await context.newPage();
    await page.goto('file://' + path.resolve(pages[0]));
    await page.waitForFunction(() => document.body.dataset.detail === 'full' || document.body.dataset.view === 'error', null, { timeout: 60000 });
    await context.close();
  }
  for (let k = 0; k < loads; ++k) {
    for (const file of pages) {
      const mb = fs.statSync(file).size / 1e6;
      const context = await browser.newContext({ viewport: { width: 1200, height: 900 } });
      const cpuAt = {};
      let cpu0 = null;
      await context.exposeFunction('__stridemapCpuAtMark', (name) => {
        const now = cpuTimes();
        cpuAt[name] = Object.fromEntries(cpuKinds.map((k) => [k, now[k] - cpu0[k]]));
      });
      await context.addInitScript(() => {
        const mark = performance.mark.bind(performance);
        performance.mark = (name, ...rest) => {
          const entry = mark(name, ...rest);
          if (String(name).startsWith('stridemap-')) window.__stridemapCpuAtMark(String(name).slice(10));
          return entry;
        };
      });
      const page = await context.newPage();
      const errors = [];
      page.on('pageerror', (e) => errors.push(e.message));
      page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
      cpu0 = cpuTimes();
      await page.goto('file://' + path.resolve(file));
      await page.waitForFunction(() => performance.getEntriesByName('stridemap-first-frame').length > 0 || document.body.dataset.view === 'error',
                                 null, { timeout: 60000 });
      // What is on the canvas when the page says its first frame is shown
      // (preserveDrawingBuffer keeps it): a blank canvas would not count.
      const drawn = await page.evaluate(() => {
        const source = document.getElementById('canvas3d'), copy = document.createElement('canvas');
        copy.width = source.width; copy.height = source.height;
        const g = copy.getContext('2d');
        g.drawImage(source, 0, 0);
        const p = g.getImageData(0, 0, copy.width, copy.height).data;
        let differ = 0;
        for (let i = 0; i < p.length; i += 4) differ += Math.abs(p[i] - 244) + Math.abs(p[i + 1] - 244) + Math.abs(p[i + 2] - 244) > 24;
        return differ / (p.length / 4);
      });
      // Pages made before the coarse level existed have no full-frame mark.
      if (await page.evaluate(() => document.querySelector('script[type=module]').textContent.includes('stridemap-full-frame'))) {
        await page.waitForFunction(() => performance.getEntriesByName('stridemap-full-frame').length > 0 || document.body.dataset.view === 'error',
                                   null, { timeout: 60000 });
      }
      const marks = await page.evaluate((names) => names.map((n) => performance.getEntriesByName(`stridemap-${n}`)[0]?.startTime), markNames);
      const first = cpuAt['first-frame'] ?? {};
      const values = [...marks, ...markNames.map((n) => cpuAt[n]?.main), ...cpuKinds.map((k) => first[k])];
      values.forEach((v, i) => { all[columns[i]].push(v); perPage.get(file)[columns[i]].push(v); });
      const name = path.relative(process.cwd(), file);
      console.log(`${name.slice(-40).padEnd(40)} ${mb.toFixed(2).padStart(5)} ${marks.map((v) => fmt(v).padStart(14)).join('')}  ${(100 * drawn).toFixed(1)} %` +
                  (errors.length ? `  errors: ${errors.join(' | ')}` : ''));
      console.log(`${''.padEnd(46)} ${markNames.map((n) => fmt(cpuAt[n]?.main).padStart(14)).join('')}  ` +
                  `${' '.repeat(16)}${cpuKinds.map((k) => fmt(first[k]).padStart(9)).join('')}`);
      await context.close();
    }
  }
} finally {
  await browser.close();
}
if (pages.length > 1) {
  for (const [file, marks] of perPage) {
    console.log(`${('median ' + path.relative(process.cwd(), file).slice(-39)).padEnd(46)} ${markNames.map((n) => fmt(median(marks[n])).padStart(14)).join('')}`);
    console.log(`${''.padEnd(46)} ${markNames.map((n) => fmt(median(marks[`cpu ${n}`])).padStart(14)).join('')}  ` +
                `${' '.repeat(16)}${cpuKinds.map((k) => fmt(median(marks[k])).padStart(9)).join('')}`);
  }
}
console.log(`${'median [ms from navigation start]'.padEnd(46)} ${markNames.map((n) => fmt(median(all[n])).padStart(14)).join('')}`);
console.log(`${'median CPU [ms]: main thread to each mark'.padEnd(46)} ${markNames.map((n) => fmt(median(all[`cpu ${n}`])).padStart(14)).join('')}  ` +
            `${' '.repeat(16)}${cpuKinds.map((k) => fmt(median(all[k])).padStart(9)).join('')}`);
console.log(`CPU at the first frame: ${cpuKinds.map((k) => `${k} = ${cpuLabel[k]}`).join(', ')}`);
console.log(`load average after: ${loadAverage()}`);
