// How long a report page takes to show its 3D view: a measurement tool, not
// a test (docs/performance.md, "The report page"). Opens each page several
// times in Debian's headless Chromium, each time in a fresh browser context,
// and prints the milliseconds from navigation start to the page's marks
// (web/report.js), the share of canvas pixels unlike the background at the
// first frame, the medians, and the machine's load average (the machine may
// be shared; the figures mean little without it).
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
const markNames = ['data-read', 'three-loaded', 'mesh-built', 'render-issued', 'first-frame', 'full-frame'];
const median = (values) => {
  const s = values.filter(Number.isFinite).sort((a, b) => a - b), h = s.length >> 1;
  return s.length === 0 ? NaN : s.length % 2 ? s[h] : (s[h - 1] + s[h]) / 2;
};
const fmt = (v) => (Number.isFinite(v) ? v.toFixed(0).padStart(6) : '     -');
const loadAverage = () => os.loadavg().map((v) => v.toFixed(2)).join(' ');

console.log(`chromium ${browser.version()}, ${os.cpus().length} cores, load average before: ${loadAverage()}`);
console.log(`${'page'.padEnd(40)} ${'MB'.padStart(5)} ${markNames.map((n) => n.padStart(14)).join('')}  non-background`);
// Round robin over the pages, so that a change in the machine's load hits
// all of them alike (pages made by two versions compare fairly).
const all = Object.fromEntries(markNames.map((n) => [n, []]));
const perPage = new Map(pages.map((file) => [file, Object.fromEntries(markNames.map((n) => [n, []]))]));
try {
  for (let k = 0; k < loads; ++k) {
    for (const file of pages) {
      const mb = fs.statSync(file).size / 1e6;
      const context = await browser.newContext({ viewport: { width: 1200, height: 900 } });
      const page = await context.newPage();
      const errors = [];
      page.on('pageerror', (e) => errors.push(e.message));
      page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
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
      marks.forEach((v, i) => { all[markNames[i]].push(v); perPage.get(file)[markNames[i]].push(v); });
      const name = path.relative(process.cwd(), file);
      console.log(`${name.slice(-40).padEnd(40)} ${mb.toFixed(2).padStart(5)} ${marks.map((v) => fmt(v).padStart(14)).join('')}  ${(100 * drawn).toFixed(1)} %` +
                  (errors.length ? `  errors: ${errors.join(' | ')}` : ''));
      await context.close();
    }
  }
} finally {
  await browser.close();
}
if (pages.length > 1) {
  for (const [file, marks] of perPage) {
    console.log(`${('median ' + path.relative(process.cwd(), file)).slice(-46).padEnd(46)} ${markNames.map((n) => fmt(median(marks[n])).padStart(14)).join('')}`);
  }
}
console.log(`${'median [ms from navigation start]'.padEnd(46)} ${markNames.map((n) => fmt(median(all[n])).padStart(14)).join('')}`);
console.log(`load average after: ${loadAverage()}`);
