// Live edits in a real browser: a feature another client posts appears without a reload (the
// change feed redraws features, legend and terrain), and a polygon drawn on the terrain in the
// page is posted with the typed token.
import assert from 'node:assert/strict';
import { after, before, test } from 'node:test';

import {
  launchChromium, makeStore, openViewer, screenshotNotBlank, serve, tempDir, waitForTerrain,
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

const counters = (page) => page.evaluate(() => {
  const { state } = window.tinbase;
  return { features: state.featureLoads, terrain: state.terrainLoads,
    txs: state.changes.map((c) => c.tx) };
});

test('a feature posted by another client appears without a reload', async () => {
  const { page, log } = await openViewer(browser, server.url);
  const { lon, lat, x, y } = await waitForTerrain(page, log, server.url);
  const before = await counters(page);
  const d = 0.01;
  const feature = {
    type: 'Feature',
    properties: { mode: 'fill', tag: 'posted-by-test' },
    geometry: { type: 'Polygon', coordinates: [[[lon - d, lat - d], [lon + d, lat - d],
      [lon + d, lat + d], [lon - d, lat + d], [lon - d, lat - d]]] },
  };
  const response = await fetch(`${server.url}/surfaces/t/features?crs=EPSG:4326`, {
    method: 'POST',
    headers: { 'Content-Type': 'application/geo+json', Authorization: `Bearer ${server.token}` },
    body: JSON.stringify(feature),
  });
  const posted = await response.json();
  assert.equal(response.status, 201, JSON.stringify(posted));

  await page.waitForSelector('#legend li[data-tag="posted-by-test"]', { timeout: 60000 });
  const now = await counters(page);
  assert.ok(now.txs.includes(posted.tx), `the page saw transactions ${now.txs}, not ${posted.tx}`);
  assert.ok(now.features > before.features && now.terrain > before.terrain,
      `features reloaded ${before.features} -> ${now.features}, ` +
      `terrain ${before.terrain} -> ${now.terrain}`);
  await waitForTerrain(page, log, server.url);
  // The triangles under the polygon now carry its tag, as the panel shows after a click.
  await page.mouse.click(x, y);
  await page.waitForSelector('#pick[data-state="located"]', { timeout: 30000 });
  assert.equal(await page.locator('#pick-tag').textContent(), 'posted-by-test');
  await screenshotNotBlank(page, 'viewer_posted_feature');
  assert.deepEqual(log.errors, []);
  await page.close();
});

test('a polygon drawn in the page is posted with the typed token', async () => {
  const { page, log } = await openViewer(browser, server.url);
  // Away from the first test's polygon, on low land clear of the DEM's voids (no elevation there).
  const { x: cx, y: cy } = await waitForTerrain(page, log, server.url, 0.25, 0.3);
  await page.click('#draw-start');
  for (const [dx, dy] of [[-30, -30], [30, -30], [30, 30], [-30, 30]]) {
    await page.mouse.click(cx + dx, cy + dy);
  }
  await page.selectOption('#draw-mode', 'fill');
  await page.fill('#draw-tag', 'drawn-in-page');
  await page.fill('#draw-token', 'not-the-token');
  await page.click('#draw-finish');
  await page.waitForSelector('#draw-status.error', { timeout: 30000 });
  assert.match(await page.locator('#draw-status').textContent(), /^Refused: .*token/i);

  await page.fill('#draw-token', server.token);
  await page.click('#draw-finish');
  await page.waitForSelector('#draw-status[data-tx]', { timeout: 60000 }).catch(async (e) => {
    throw new Error(`${e.message}: ${await page.locator('#draw-status').textContent()}`);
  });
  const tx = Number(await page.getAttribute('#draw-status', 'data-tx'));
  await page.waitForSelector('#legend li[data-tag="drawn-in-page"]', { timeout: 60000 });
  assert.ok((await counters(page)).txs.includes(tx));
  // The globe reloads its tiles after the change; click once they are back.
  await waitForTerrain(page, log, server.url, 0.25, 0.3);
  await page.mouse.click(cx, cy);
  await page.waitForSelector('#pick[data-state="located"]', { timeout: 30000 });
  assert.equal(await page.locator('#pick-tag').textContent(), 'drawn-in-page',
      JSON.stringify(await page.evaluate(() => ({ picked: window.tinbase.picker.last,
        drawn: window.tinbase.state.features.geojson }))));
  await screenshotNotBlank(page, 'viewer_drawn_feature');
  // The refused post logs a 401 in the console; nothing else may fail.
  assert.deepEqual(log.errors.filter((e) => !/401/.test(e)), []);
  await page.close();
});
