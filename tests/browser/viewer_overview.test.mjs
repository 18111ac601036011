// The DEM overview in a real browser: the hillshade image, a box dragged on it, and the TIN of the
// box at the chosen face budget shown on the globe.
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

test('a box dragged on the DEM overview shows its TIN', async () => {
  const { page, log } = await openViewer(browser, server.url);
  await waitForTerrain(page, log, server.url);
  await page.waitForFunction(() => {
    const image = document.getElementById('overview-image');
    return image.complete && image.naturalWidth > 0;
  }, null, { timeout: 30000 });
  const image = await page.locator('#overview-image').boundingBox();
  await page.mouse.move(image.x + image.width * 0.4, image.y + image.height * 0.4);
  await page.mouse.down();
  await page.mouse.move(image.x + image.width * 0.5, image.y + image.height * 0.5, { steps: 5 });
  await page.mouse.up();
  assert.equal(await page.isEnabled('#show-tin'), true);
  await page.fill('#faces', '5000');
  const tinRequest = page.waitForResponse((r) => r.url().includes('/tin?'));
  await page.click('#show-tin');
  const response = await tinRequest;
  assert.equal(response.status(), 200);
  assert.match(response.url(), /faces=5000/);
  await page.waitForSelector('#tin-status[data-loaded="1"]', { timeout: 60000 });
  // Seen from above the box, with the globe hidden, only the TIN model can fill the picture.
  await page.evaluate(() => {
    const { viewer, overview, Cesium } = window.tinbase;
    viewer.scene.globe.show = false;
    const [w, s, e, n] = overview.lonlatBox();
    viewer.camera.setView({ destination: Cesium.Rectangle.fromDegrees(w, s, e, n) });
  });
  await page.waitForFunction(() => window.tinbase.overview.model.ready, null, { timeout: 60000 });
  await page.waitForTimeout(500);
  await screenshotNotBlank(page, 'viewer_overview_tin');
  assert.deepEqual(log.errors, []);
  await page.close();
});
