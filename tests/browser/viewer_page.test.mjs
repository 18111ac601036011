// The viewer in a real browser: it loads from the service alone, draws our terrain tiles, and a
// click on the terrain shows the located triangle (id, z, tag) and outlines its neighbours.
import assert from 'node:assert/strict';
import { after, before, test } from 'node:test';

import {
  assertOnlyLocalRequests, getJson, launchChromium, makeStore, openViewer, screenshotNotBlank,
  serve, tempDir, waitForTerrain,
} from './support.mjs';

let server;
let browser;

before(async () => {
  const dir = tempDir();
  server = await serve(makeStore(dir), dir);
  browser = await launchChromium();
});

after(async () => {
  await browser?.close();
  await server?.stop();
});

test('the page draws the terrain tiles and a click shows the located triangle', async () => {
  const { page, log } = await openViewer(browser, server.url);
  const at = await waitForTerrain(page, log, server.url);
  await screenshotNotBlank(page, 'viewer_terrain');

  await page.mouse.click(at.x, at.y);
  await page.waitForSelector('#pick[data-state="located"]', { timeout: 30000 });
  const shown = await page.locator('#pick-triangle').textContent();
  const picked = await page.evaluate(() => window.tinbase.picker.last);
  // The panel shows what the service answers for the clicked point, not something the page made.
  const answer = await getJson(server.url, `/surfaces/t/locate?x=${picked.x}&y=${picked.y}`);
  assert.equal(shown, String(answer.triangle.id));
  assert.equal(await page.locator('#pick-z').textContent(), answer.z.toFixed(2));
  assert.equal(await page.locator('#pick-tag').textContent(), answer.triangle.tag ?? '(none)');
  assert.ok(Math.abs(answer.z - at.height) < 60, `clicked z ${answer.z}, globe ${at.height}`);
  // The triangle and its visible neighbours are outlined.
  await page.waitForSelector('#pick[data-highlighted]', { timeout: 30000 });
  const visibleNeighbours = (await getJson(server.url, `/surfaces/t/triangles/${shown}`))
      .neighbours.filter((n) => n && n.visible !== false).length;
  assert.equal(Number(await page.getAttribute('#pick', 'data-highlighted')), visibleNeighbours + 1);
  // Close enough to see the outlines in the screenshot.
  await page.evaluate((lonlat) => {
    const { viewer, Cesium } = window.tinbase;
    const lons = lonlat.map((p) => p[0]);
    const lats = lonlat.map((p) => p[1]);
    const size = (v) => Math.max(...v) - Math.min(...v);
    const pad = 4 * Math.max(size(lons), size(lats));
    viewer.camera.setView({ destination: Cesium.Rectangle.fromDegrees(Math.min(...lons) - pad,
        Math.min(...lats) - pad, Math.max(...lons) + pad, Math.max(...lats) + pad) });
  }, answer.triangle.lonlat);
  await screenshotNotBlank(page, 'viewer_click');

  // The check fails on a globe that draws nothing.
  await page.evaluate(() => { window.tinbase.viewer.scene.globe.show = false; });
  await assert.rejects(screenshotNotBlank(page, 'viewer_blank_on_purpose'), /looks blank/);

  assertOnlyLocalRequests(log, server.url);
  assert.deepEqual(log.errors, []);
  await page.close();
});
