#!/usr/bin/env node
// Headless render of a luxbake output as a glTF viewer shows it (three.js GLTFLoader, materials
// as loaded) in headless Chromium with software GL (SwiftShader). No network: a local server
// on 127.0.0.1 serves page.html, three from node_modules and the glTF's folder.
//
//   node bench/render/render.mjs LIT.gltf OUT.png (--eye X,Y,Z --target X,Y,Z [--fov DEG]
//        [--up X,Y,Z] | --camera NAME) [--size WxH] [--near M] [--chromium PATH]
//
// Camera: perspective, vertical field of view in degrees, world axes of glTF (+Y up), metres.
// --camera NAME uses the glTF camera node of that name (its world matrix, yfov and znear, unless
// --near is given); the aspect is always the image's W/H, not the camera's aspectRatio, as
// `bake view --camera` does.
import { spawn } from 'node:child_process';
import { createServer } from 'node:http';
import { mkdtempSync, readFileSync, rmSync, statSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { basename, dirname, extname, join, resolve, sep } from 'node:path';
import { fileURLToPath } from 'node:url';
import { deflateSync } from 'node:zlib';

const HERE = dirname(fileURLToPath(import.meta.url));
const USAGE = 'usage: render.mjs LIT.gltf OUT.png (--eye X,Y,Z --target X,Y,Z [--fov DEG] ' +
  '[--up X,Y,Z] | --camera NAME) [--size WxH] [--near M] [--chromium PATH]';
const TIMEOUT_MS = 120_000;

function die(msg) { console.error(`render.mjs: ${msg}`); process.exit(2); }

function parseArgs(argv) {
  const defaults = { fov: '50', size: '1000x750', up: '0,1,0', near: '0.01', chromium: 'chromium' };
  const opt = {};
  const pos = [];
  for (let i = 0; i < argv.length; i++) {
    if (argv[i].startsWith('--')) {
      const key = argv[i].slice(2);
      if (!(key in defaults) && !['eye', 'target', 'camera'].includes(key)) {
        die(`unknown option ${argv[i]}\n${USAGE}`);
      }
      if (i + 1 >= argv.length) die(`${argv[i]} needs a value`);
      opt[key] = argv[++i];
    } else pos.push(argv[i]);
  }
  if (pos.length !== 2) die(USAGE);
  if (opt.camera !== undefined) {
    const clash = ['eye', 'target', 'fov', 'up'].filter((k) => k in opt);
    if (clash.length) die(`--camera takes the view from the glTF: drop --${clash.join(', --')}`);
    if (!opt.camera) die('--camera wants a node name');
  } else if (!opt.eye || !opt.target) die(USAGE);
  // --near given: it wins; else the camera's znear with --camera, 0.01 m without.
  const nearGiven = 'near' in opt;
  for (const [k, v] of Object.entries(defaults)) if (!(k in opt)) opt[k] = v;
  if (!nearGiven && opt.camera !== undefined) opt.near = '';
  const triple = /^-?[\d.e+-]+,-?[\d.e+-]+,-?[\d.e+-]+$/;
  for (const k of ['eye', 'target', 'up']) {
    if (opt[k] !== undefined && !triple.test(opt[k])) die(`--${k} wants X,Y,Z`);
  }
  if (opt.near !== '' && !(Number(opt.near) > 0)) die('--near wants metres > 0');
  if (!/^\d+x\d+$/.test(opt.size)) die('--size wants WxH');
  if (!(Number(opt.fov) > 0 && Number(opt.fov) < 180)) die('--fov wants degrees in (0, 180)');
  const [w, h] = opt.size.split('x').map(Number);
  return { input: resolve(pos[0]), output: resolve(pos[1]), w, h, ...opt };
}

const MIME = { '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript',
  '.gltf': 'model/gltf+json', '.glb': 'model/gltf-binary', '.bin': 'application/octet-stream',
  '.png': 'image/png', '.jpg': 'image/jpeg', '.jpeg': 'image/jpeg' };

// Maps a URL path to a file under one of the served roots, or null.
function fileFor(urlPath, roots) {
  for (const [prefix, root] of roots) {
    if (!urlPath.startsWith(prefix)) continue;
    const file = resolve(root, '.' + decodeURIComponent(urlPath.slice(prefix.length - 1)));
    if (file === root || file.startsWith(root + sep)) return file;
  }
  return null;
}

const readBody = (req) => new Promise((ok) => {
  const parts = [];
  req.on('data', (c) => parts.push(c));
  req.on('end', () => ok(Buffer.concat(parts)));
});

// PNG (8-bit RGB) of RGBA pixels given bottom row first, as WebGL reads them. Each row gets the
// filter of least absolute sum (the usual heuristic), then zlib level 9: smaller than Chromium's.
const CRC = Array.from({ length: 256 }, (_, n) => {
  let c = n;
  for (let k = 0; k < 8; k++) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
  return c >>> 0;
});
function crc32(buf) {
  let c = 0xffffffff;
  for (const b of buf) c = CRC[(c ^ b) & 255] ^ (c >>> 8);
  return (c ^ 0xffffffff) >>> 0;
}
function chunk(type, data) {
  const out = Buffer.alloc(12 + data.length);
  out.writeUInt32BE(data.length, 0);
  out.write(type, 4, 'latin1');
  data.copy(out, 8);
  out.writeUInt32BE(crc32(out.subarray(4, 8 + data.length)), 8 + data.length);
  return out;
}
function encodePng(rgba, w, h) {
  const row = w * 3;
  const raw = Buffer.alloc((row + 1) * h);
  let prev = Buffer.alloc(row);
  const cur = Buffer.alloc(row);
  const cand = Buffer.alloc(row);
  for (let y = 0; y < h; y++) {
    const src = (h - 1 - y) * w * 4;
    for (let x = 0; x < w; x++) for (let c = 0; c < 3; c++) cur[x * 3 + c] = rgba[src + x * 4 + c];
    let best = null;
    let bestSum = Infinity;
    for (let f = 0; f < 5; f++) {
      let sum = 0;
      for (let i = 0; i < row; i++) {
        const a = i >= 3 ? cur[i - 3] : 0;
        const b = prev[i];
        const c = i >= 3 ? prev[i - 3] : 0;
        let pred = 0;
        if (f === 1) pred = a;
        else if (f === 2) pred = b;
        else if (f === 3) pred = (a + b) >> 1;
        else if (f === 4) {
          const p = a + b - c;
          const pa = Math.abs(p - a), pb = Math.abs(p - b), pc = Math.abs(p - c);
          pred = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
        }
        const v = (cur[i] - pred) & 255;
        cand[i] = v;
        sum += v < 128 ? v : 256 - v;
      }
      if (sum < bestSum) { bestSum = sum; best = [f, Buffer.from(cand)]; }
    }
    raw[y * (row + 1)] = best[0];
    best[1].copy(raw, y * (row + 1) + 1);
    prev = Buffer.from(cur);
  }
  const ihdr = Buffer.alloc(13);
  ihdr.writeUInt32BE(w, 0);
  ihdr.writeUInt32BE(h, 4);
  ihdr.set([8, 2, 0, 0, 0], 8);
  return Buffer.concat([Buffer.from([137, 80, 78, 71, 13, 10, 26, 10]), chunk('IHDR', ihdr),
    chunk('IDAT', deflateSync(raw, { level: 9 })), chunk('IEND', Buffer.alloc(0))]);
}

async function main() {
  const a = parseArgs(process.argv.slice(2));
  try { statSync(a.input); } catch { die(`no such file: ${a.input}`); }
  const three = join(HERE, 'node_modules', 'three');
  try { statSync(join(three, 'build', 'three.module.js')); } catch {
    die(`three is not installed: run bench/render/install.sh (or npm ci in ${HERE})`);
  }
  const roots = [['/three/', three], ['/scene/', dirname(a.input)]];
  const profile = mkdtempSync(join(tmpdir(), 'luxbake-render-'));
  let browser = null;
  let finish;
  const finished = new Promise((ok) => { finish = ok; });
  let pixels = null;

  const server = createServer(async (req, res) => {
    const path = new URL(req.url, 'http://x').pathname;
    if (req.method === 'POST') {
      const body = await readBody(req);
      res.end();
      if (path === '/result') pixels = body;
      else if (path === '/log') console.error(`render.mjs: ${body}`);
      else if (path === '/done') finish(null);
      else if (path === '/error') finish(`page error: ${body}`);
      return;
    }
    const file = path === '/' ? join(HERE, 'page.html') : fileFor(path, roots);
    try {
      const data = readFileSync(file);
      res.writeHead(200, { 'content-type': MIME[extname(file)] || 'application/octet-stream' });
      res.end(data);
    } catch {
      res.writeHead(404);
      res.end();
    }
  });
  await new Promise((ok) => server.listen(0, '127.0.0.1', ok));
  const query = new URLSearchParams(a.camera !== undefined
    ? { file: basename(a.input), size: a.size, camera: a.camera, near: a.near }
    : { file: basename(a.input), size: a.size, fov: a.fov, eye: a.eye, target: a.target,
      up: a.up, near: a.near });
  const url = `http://127.0.0.1:${server.address().port}/?${query}`;

  browser = spawn(a.chromium, [
    '--headless', '--no-sandbox', '--no-first-run', '--no-default-browser-check',
    '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist',
    '--force-device-scale-factor=1', `--window-size=${a.w},${a.h}`, `--user-data-dir=${profile}`,
    '--disable-extensions', '--disable-background-networking', '--disable-component-update',
    '--disable-sync', '--metrics-recording-only', '--no-pings', url,
  ], { stdio: ['ignore', 'ignore', 'pipe'], detached: true }); // own group: ended as one
  let stderr = '';
  browser.stderr.on('data', (c) => { stderr = (stderr + c).slice(-4000); });
  browser.on('error', (e) => finish(`cannot start ${a.chromium}: ${e.message} (bench/render/install.sh installs it)`));
  browser.on('exit', (code) => finish(`chromium exited (${code}) before the render:\n${stderr}`));
  const timer = setTimeout(() => finish(`no render after ${TIMEOUT_MS / 1000} s`), TIMEOUT_MS);

  const error = await finished;
  clearTimeout(timer);
  browser.removeAllListeners('exit');
  if (browser.exitCode === null && browser.pid) {
    const gone = new Promise((ok) => browser.once('exit', ok));
    try { process.kill(-browser.pid, 'SIGTERM'); } catch { browser.kill('SIGTERM'); }
    await gone;
  }
  server.close();
  const ok = !error && pixels && pixels.length === a.w * a.h * 4;
  if (ok) writeFileSync(a.output, encodePng(pixels, a.w, a.h));
  // Chromium's helpers may still be leaving: retry the profile's removal.
  rmSync(profile, { recursive: true, force: true, maxRetries: 10, retryDelay: 200 });
  if (error) die(error);
  if (!ok) die(`the page sent ${pixels ? pixels.length : 0} bytes, not ${a.size} RGBA pixels`);
  console.error(`render.mjs: wrote ${a.output} (${a.size})`);
}

main().catch((e) => die(e.stack || String(e)));
