// Shared pieces of the browser tests: a store with terrain tiles made with the tinbase CLI,
// `tinbase serve` on it at a free loopback port, Debian's chromium driven by playwright-core,
// and screenshots saved as test artifacts with a check that the globe is not blank.
//
// The environment (set by tests/CMakeLists.txt): TINBASE_CLI (the tinbase binary),
// TINBASE_SOURCE_DIR (the repository: test data and web/dist), TINBASE_ARTIFACTS (where
// screenshots go), optionally TINBASE_CHROMIUM (default /usr/bin/chromium).
import assert from 'node:assert/strict';
import { execFileSync, spawn } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';

function requiredEnv(name) {
  const value = process.env[name];
  assert.ok(value, `${name} is not set (the browser tests run under CTest, which sets it)`);
  return value;
}

export const cli = requiredEnv('TINBASE_CLI');
export const sourceDir = requiredEnv('TINBASE_SOURCE_DIR');
export const artifactDir = requiredEnv('TINBASE_ARTIFACTS');
export const webRoot = path.join(sourceDir, 'web', 'dist');
const chromiumPath = process.env.TINBASE_CHROMIUM || '/usr/bin/chromium';

function run(...args) {
  return execFileSync(cli, args, { encoding: 'utf8', stdio: ['ignore', 'pipe', 'pipe'] });
}

// A new temporary directory, removed when the process exits.
export function tempDir() {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'tinbase-browser-'));
  process.on('exit', () => fs.rmSync(dir, { recursive: true, force: true }));
  return dir;
}

// A store in `dir` holding the DEM N43E007, the surface "t" built on it (tolerance 20 m) and its
// terrain tiles; returns the store's path.
export function makeStore(dir) {
  const store = path.join(dir, 'viewer.tinbase');
  run('init', store);
  run('dem', 'import', store, path.join(sourceDir, 'tests', 'data', 'dem', 'N43E007.hgt'));
  run('tin', 'build', store, '--surface', 't', '--tolerance', '20');
  run('tiles', 'build', store, '--surface', 't', '--extensions', 'octvertexnormals');
  return store;
}

// Runs `tinbase serve store` on 127.0.0.1 at a free port with the viewer and a write token;
// resolves to {url, token, stop()} once it listens.
export async function serve(store, dir) {
  for (const file of ['index.html', 'main.js', 'cesium/index.js']) {
    assert.ok(fs.existsSync(path.join(webRoot, file)),
        `${webRoot}/${file} is missing: scripts/build-web.sh builds the viewer`);
  }
  const token = 'browser-test-token';
  const tokenFile = path.join(dir, 'token');
  fs.writeFileSync(tokenFile, `${token}\n`);
  const child = spawn(cli, ['serve', store, '--listen', '127.0.0.1:0', '--web-root', webRoot,
    '--token-file', tokenFile], { stdio: ['ignore', 'pipe', 'pipe'] });
  let stderr = '';
  child.stderr.on('data', (d) => { stderr += d; });
  const url = await new Promise((resolve, reject) => {
    let out = '';
    const fail = () => reject(new Error(`tinbase serve did not start: ${stderr}`));
    const timer = setTimeout(fail, 30000);
    child.stdout.on('data', (d) => {
      out += d;
      const port = out.match(/http:\/\/127\.0\.0\.1:(\d+)\//);
      if (port) {
        clearTimeout(timer);
        resolve(`http://127.0.0.1:${port[1]}`);
      }
    });
    child.on('exit', (code) => reject(new Error(`tinbase serve exited (${code}): ${stderr}`)));
  });
  const stop = () => new Promise((resolve) => {
    if (child.exitCode !== null) return resolve();
    child.on('exit', resolve);
    child.kill('SIGTERM');
  });
  process.on('exit', () => child.kill('SIGKILL'));
  return { url, token, stop };
}

// Debian's chromium through playwright-core; WebGL runs on SwiftShader, so no GPU is needed.
export async function launchChromium() {
  assert.ok(fs.existsSync(chromiumPath),
      `${chromiumPath} is missing: scripts/install-deps.sh installs Debian's chromium`);
  let chromium;
  try {
    ({ chromium } = await import('playwright-core'));
  } catch (e) {
    assert.fail('playwright-core is not installed (scripts/build-web.sh --browser-tests): ' +
        e.message);
  }
  return chromium.launch({
    executablePath: chromiumPath,
    args: ['--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist',
      '--no-sandbox'],
  });
}

// A page of `browser` at the viewer; every request it makes is recorded, and console errors and
// page errors are kept for the test to show.
export async function openViewer(browser, url) {
  const page = await browser.newPage({ viewport: { width: 1024, height: 700 } });
  const log = { requests: [], terrain: [], errors: [] };
  page.on('request', (r) => log.requests.push(r.url()));
  page.on('response', (r) => {
    if (/\/tiles\/\d+\/\d+\/\d+\.terrain/.test(r.url())) log.terrain.push(r.status());
  });
  page.on('pageerror', (e) => log.errors.push(`page error: ${e.message}`));
  page.on('console', (m) => { if (m.type() === 'error') log.errors.push(`console: ${m.text()}`); });
  await page.goto(`${url}/`);
  await page.waitForSelector('body[data-ready="true"]', { timeout: 60000 }).catch((e) => {
    throw new Error(`the viewer did not get ready: ${e.message}\n${log.errors.join('\n')}`);
  });
  return { page, log };
}

// The point of the globe at fractions (fx, fy) of its canvas, where the view shows land on the
// test surface: its window position, lon/lat and the terrain height the globe has there, once
// the globe has loaded every tile it wants. Null fields while nothing is drawn there.
function terrainAt(page, fx, fy) {
  return page.evaluate(([fx, fy]) => {
    const { viewer, Cesium } = window.tinbase;
    const canvas = viewer.scene.canvas;
    const position = new Cesium.Cartesian2(canvas.clientWidth * fx, canvas.clientHeight * fy);
    const ray = viewer.camera.getPickRay(position);
    const point = ray && viewer.scene.globe.pick(ray, viewer.scene);
    if (!viewer.scene.globe.tilesLoaded || !point) return null;
    const c = Cesium.Cartographic.fromCartesian(point);
    const rect = canvas.getBoundingClientRect();
    return {
      lon: Cesium.Math.toDegrees(c.longitude),
      lat: Cesium.Math.toDegrees(c.latitude),
      height: viewer.scene.globe.getHeight(c) ?? null,
      x: rect.left + position.x,
      y: rect.top + position.y,
    };
  }, [fx, fy]);
}

// Waits until terrain tiles were requested and decoded: the globe has loaded every tile it
// wants, and its height at the point (fx, fy) of the view agrees with the surface's z there
// (GET locate) within 60 m: above the error bounds of the levels drawn at this view, far below
// the relief there (the points the tests pick are a few hundred metres up, while the flat filler
// tiles above a small pyramid stand at the surface's lowest height).
export async function waitForTerrain(page, log, url, fx = 0.5, fy = 0.12) {
  let at = null;
  let z = null;
  const deadline = Date.now() + 120000;
  while (Date.now() < deadline) {
    at = await terrainAt(page, fx, fy);
    if (at && at.height !== null) {
      const response = await fetch(`${url}/surfaces/t/locate?lon=${at.lon}&lat=${at.lat}`);
      z = response.ok ? (await response.json()).z : null;
      if (z !== null && Math.abs(at.height - z) < 60) break;
    }
    await page.waitForTimeout(500);
  }
  assert.ok(at && z !== null && Math.abs(at.height - z) < 60,
      `the globe at (${fx}, ${fy}) of the view, ${JSON.stringify(at)}, does not show the ` +
      `surface's z ${z} there`);
  assert.ok(z > 100, `the test point should be on land, but the surface's z there is ${z}`);
  assert.ok(log.terrain.length > 0, 'the page requested no terrain tile');
  assert.ok(log.terrain.every((s) => s === 200 || s === 304), `tile answers: ${log.terrain}`);
  console.log(`# terrain at (${fx}, ${fy}): globe ${at.height.toFixed(1)} m, ` +
      `surface ${z.toFixed(1)} m`);
  return at;
}

// Waits until the globe has its tiles and every entity (features, outlines) is drawn: ground
// primitives are built asynchronously, a little after the entities are added.
export async function waitForDrawn(page) {
  await page.waitForFunction(() => {
    const { viewer } = window.tinbase;
    return viewer.scene.globe.tilesLoaded && viewer.dataSourceDisplay.ready;
  }, null, { timeout: 120000, polling: 250 });
  // One more frame, so the screenshot has what the last update made.
  await page.evaluate(() => new Promise((resolve) => requestAnimationFrame(() => resolve())));
}

// Saves a screenshot of the page as artifact `name`.png and fails when the globe's part of it
// is blank (one flat colour): a WebGL failure or a globe that drew nothing.
export async function screenshotNotBlank(page, name) {
  await waitForDrawn(page);
  fs.mkdirSync(artifactDir, { recursive: true });
  const file = path.join(artifactDir, `${name}.png`);
  await page.screenshot({ path: file });
  // A clipped page shot: an element shot waits for the element to be still between animation
  // frames, which a globe rendering on the CPU rarely is.
  // Without Cesium's credit logo, which is drawn over the globe whatever the globe shows.
  await page.evaluate(() => {
    document.querySelector('.cesium-widget-credits').style.visibility = 'hidden';
  });
  const globe = await page.screenshot({ clip: await page.locator('#globe').boundingBox() });
  await page.evaluate(() => {
    document.querySelector('.cesium-widget-credits').style.visibility = '';
  });
  const stats = await page.evaluate(async (base64) => {
    const image = new Image();
    image.src = `data:image/png;base64,${base64}`;
    await image.decode();
    const canvas = document.createElement('canvas');
    canvas.width = image.width;
    canvas.height = image.height;
    const context = canvas.getContext('2d');
    context.drawImage(image, 0, 0);
    const { data } = context.getImageData(0, 0, image.width, image.height);
    const colours = new Set();
    let sum = 0;
    let sumSquares = 0;
    const n = data.length / 4;
    for (let i = 0; i < data.length; i += 4) {
      const luma = 0.299 * data[i] + 0.587 * data[i + 1] + 0.114 * data[i + 2];
      sum += luma;
      sumSquares += luma * luma;
      if (colours.size < 10000) colours.add((data[i] << 16) | (data[i + 1] << 8) | data[i + 2]);
    }
    const mean = sum / n;
    return { colours: colours.size, deviation: Math.sqrt(sumSquares / n - mean * mean) };
  }, globe.toString('base64'));
  assert.ok(stats.colours > 64 && stats.deviation > 4,
      `the globe looks blank in ${file} (${stats.colours} colours, luma deviation ` +
      `${stats.deviation.toFixed(2)})`);
  return file;
}

// Every request of the page went to the service itself (no CDN, no Cesium ion).
export function assertOnlyLocalRequests(log, url) {
  const foreign = log.requests.filter((r) => !r.startsWith(`${url}/`) && !/^(data|blob):/.test(r));
  assert.deepEqual(foreign, [], 'the page reached outside the service');
}

// GET `path` of the service as JSON.
export async function getJson(url, pathAndQuery) {
  const response = await fetch(`${url}${pathAndQuery}`);
  const body = await response.json();
  assert.ok(response.ok, `GET ${pathAndQuery}: ${response.status} ${JSON.stringify(body)}`);
  return body;
}
