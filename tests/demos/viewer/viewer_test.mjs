// Opens a demo run in the browser viewer as a person would (scripts/view.sh, headless Chromium
// driven by puppeteer-core) and checks what is shown: the canvas is not blank, every body's
// colour is in it, and the counts shown for the first and the last frame are summary.json's.
//   node viewer_test.mjs VIEWER_DIR RUN_DIR VIEW_SCRIPT SCREENSHOT.png
// Prints "SKIPPED: ..." and exits 0 only when Chromium is not installed or cannot start.
import { spawn } from 'node:child_process';
import { existsSync, readFileSync } from 'node:fs';
import { createRequire } from 'node:module';

const [viewerDir, runDir, viewScript, screenshot] = process.argv.slice(2);
const chromium = ['/usr/bin/chromium', '/usr/bin/chromium-browser'].find(existsSync);
if (!chromium) {
  console.log('SKIPPED: Chromium is not installed (Debian: apt-get install chromium)');
  process.exit(0);
}
const puppeteer = createRequire(`${viewerDir}/package.json`)('puppeteer-core');
const summary = JSON.parse(readFileSync(`${runDir}/summary.json`, 'utf8'));
const failures = [];
const check = (ok, what) => { if (!ok) failures.push(what); };

// The viewer's server, on a port of its own; its address is the line it prints.
const port = String(20000 + (process.pid % 20000));
const server = spawn(viewScript, [runDir, port], { detached: true, stdio: ['ignore', 'pipe', 'inherit'] });
const stop = () => { try { process.kill(-server.pid, 'SIGTERM'); } catch { /* already gone */ } };
const url = await new Promise((resolve, reject) => {
  let text = '';
  server.stdout.on('data', (d) => {
    text += d;
    const m = text.match(/http:\/\/127\.0\.0\.1:\d+\//);
    if (m) resolve(m[0]);
  });
  server.on('exit', (code) => reject(new Error(`scripts/view.sh exited (${code}) before serving`)));
  setTimeout(() => reject(new Error('scripts/view.sh printed no address in 60 s')), 60000);
});

let browser;
try {
  browser = await puppeteer.launch({
    executablePath: chromium,
    headless: true,
    // Software WebGL: CI machines have no GPU.
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'],
  });
} catch (e) {
  stop();
  console.log(`SKIPPED: Chromium cannot start: ${e.message.split('\n')[0]}`);
  process.exit(0);
}

try {
  const page = await browser.newPage();
  await page.setViewport({ width: 1280, height: 720 });
  // The server may take a moment to listen after printing its address.
  for (let i = 0; ; ++i) {
    try { await page.goto(`${url}?paused`, { waitUntil: 'load' }); break; } catch (e) { if (i > 20) throw e; await new Promise((r) => setTimeout(r, 250)); }
  }
  await page.waitForFunction(() => window.viewerState.ready || window.viewerState.error, { timeout: 60000 });
  const state = await page.evaluate(() => window.viewerState);
  check(!state.error, `the viewer could not load the run: ${state.error}`);
  await new Promise((r) => setTimeout(r, 500)); // a few more frames drawn
  await page.screenshot({ path: screenshot });

  // The picture, read back from the WebGL canvas.
  const picture = await page.evaluate(() => {
    const gl = document.querySelector('#view canvas');
    const c = document.createElement('canvas');
    c.width = gl.width; c.height = gl.height;
    const g = c.getContext('2d');
    g.drawImage(gl, 0, 0);
    return { width: c.width, height: c.height, data: Array.from(g.getImageData(0, 0, c.width, c.height).data) };
  });
  const hsv = (r, g, b) => {
    const max = Math.max(r, g, b), min = Math.min(r, g, b), d = max - min;
    let h = 0;
    if (d > 0) h = max === r ? ((g - b) / d) % 6 : max === g ? (b - r) / d + 2 : (r - g) / d + 4;
    return [(h * 60 + 360) % 360, max > 0 ? d / max : 0, max / 255];
  };
  const background = picture.data.slice(0, 3).join(',');
  let differ = 0;
  const hues = [];
  for (let i = 0; i < picture.data.length; i += 4) {
    const [r, g, b] = [picture.data[i], picture.data[i + 1], picture.data[i + 2]];
    if (`${r},${g},${b}` !== background) ++differ;
    const [h, s, v] = hsv(r, g, b);
    if (s > 0.2 && v > 0.15) hues.push(h);
  }
  const pixels = picture.data.length / 4;
  check(differ > 0.02 * pixels, `the canvas is blank: ${differ} of ${pixels} pixels differ from the background`);
  for (const colour of state.colours) {
    const [h] = hsv(parseInt(colour.slice(1, 3), 16), parseInt(colour.slice(3, 5), 16), parseInt(colour.slice(5, 7), 16));
    const near = hues.filter((x) => Math.min(Math.abs(x - h), 360 - Math.abs(x - h)) < 12).length;
    check(near >= 30, `body colour ${colour} (hue ${h.toFixed(0)}°) is not in the picture (${near} pixels)`);
  }
  check(state.colours.length > 0, 'no body colour in the scene');

  // The counts shown, at the first frame and (through the timeline) at the last.
  const shown = () => page.evaluate(() => ({
    frame: window.viewerState.frame,
    bodies: document.getElementById('bodies').textContent,
    events: document.getElementById('events').textContent,
  }));
  for (const frame of [1, summary.frames]) {
    if (frame !== 1)
      await page.evaluate((f) => {
        const t = document.getElementById('timeline');
        t.value = f;
        t.dispatchEvent(new Event('input'));
      }, frame);
    const s = await shown();
    check(s.frame === frame, `the viewer shows frame ${s.frame}, expected ${frame}`);
    check(s.bodies === String(summary.bodies_per_frame[frame - 1]),
          `frame ${frame}: ${s.bodies} bodies shown, summary.json says ${summary.bodies_per_frame[frame - 1]}`);
    check(s.events === String(summary.events_per_frame[frame - 1]),
          `frame ${frame}: ${s.events} events shown, summary.json says ${summary.events_per_frame[frame - 1]}`);
  }
} finally {
  await browser.close();
  stop();
}
if (failures.length) {
  for (const f of failures) console.log(`FAIL: ${f}`);
  process.exit(1);
}
console.log(`viewer OK: ${screenshot}`);
process.exit(0);
