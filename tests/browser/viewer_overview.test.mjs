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
  // A box on the mountains in the north of the DEM.
  await page.mouse.move(image.x + image.width * 0.35, image.y + image.height * 0.08);
  await page.mouse.down();
  await page.mouse.move(image.x + image.width * 0.5, image.y + image.height * 0.22, { steps: 5 });
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
  // The model stands where the box is, on the ground: its centre is inside the box and at a
  // height of the terrain there, so the frame's origin and axes were read right.
  const placed = await page.evaluate(() => {
    const { overview, Cesium } = window.tinbase;
    const c = Cesium.Cartographic.fromCartesian(overview.model.boundingSphere.center);
    return { lon: Cesium.Math.toDegrees(c.longitude), lat: Cesium.Math.toDegrees(c.latitude),
      height: c.height, box: overview.lonlatBox() };
  });
  const [w, s, e, n] = placed.box;
  assert.ok(placed.lon > w && placed.lon < e && placed.lat > s && placed.lat < n,
      `the TIN's centre ${placed.lon}, ${placed.lat} is outside the box ${placed.box}`);
  assert.ok(placed.height > 0 && placed.height < 3000, `the TIN's centre is at ${placed.height} m`);
  await screenshotNotBlank(page, 'viewer_overview_tin');
  assert.deepEqual(log.errors, []);
  await page.close();
});
