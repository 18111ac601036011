// The DEM overview map: the hillshade image of a DEM, a box dragged on it, and the TIN of that box
// (GET /dems/{d}/tin, a GLB in an east-north-up frame) placed on the globe at the frame's origin.
import * as Cesium from './cesium/index.js';
import { ApiError, getBlob, parseNumbers } from './api.js';

export class OverviewMap {
  constructor(viewer, elements) {
    this.viewer = viewer;
    this.el = elements;  // {image, box, frame, faces, button, status}
    this.dem = null;
    this.drag = null;    // the box in image fractions {x0, y0, x1, y1}
    this.model = null;
    this.boxEntity = null;
    this.loaded = 0;     // TIN models shown so far (for tests)
    this.listen();
  }

  // Shows DEM `dem`'s overview image (a hillshade in lon/lat, north up, spanning the box of its
  // X-Tinbase-Bbox-Lonlat header).
  async show(dem) {
    this.dem = dem;
    this.drag = null;
    this.el.box.style.display = 'none';
    this.el.button.disabled = true;
    const { blob, headers } = await getBlob(`/dems/${encodeURIComponent(dem.name)}/overview.png`);
    this.imageBox = parseNumbers(headers.get('X-Tinbase-Bbox-Lonlat'), 4) || dem.bbox_lonlat;
    this.el.image.src = URL.createObjectURL(blob);
    await this.el.image.decode();
  }

  listen() {
    const frame = this.el.frame;
    const fraction = (event) => {
      const r = this.el.image.getBoundingClientRect();
      return {
        x: Math.min(1, Math.max(0, (event.clientX - r.left) / r.width)),
        y: Math.min(1, Math.max(0, (event.clientY - r.top) / r.height)),
      };
    };
    let start = null;
    frame.addEventListener('pointerdown', (event) => {
      if (!this.dem) return;
      start = fraction(event);
      frame.setPointerCapture(event.pointerId);
      event.preventDefault();
    });
    frame.addEventListener('pointermove', (event) => {
      if (start) this.setBox(start, fraction(event));
    });
    frame.addEventListener('pointerup', (event) => {
      if (!start) return;
      this.setBox(start, fraction(event));
      start = null;
      const d = this.drag;
      const big = d.x1 - d.x0 > 0.005 && d.y1 - d.y0 > 0.005;
      this.el.button.disabled = !big;
      this.el.status.textContent = big ? `Box ${this.bboxText()}` : 'Drag a larger box.';
    });
    this.el.button.addEventListener('click', () => this.showTin());
  }

  setBox(a, b) {
    this.drag = { x0: Math.min(a.x, b.x), y0: Math.min(a.y, b.y), x1: Math.max(a.x, b.x),
      y1: Math.max(a.y, b.y) };
    const s = this.el.box.style;
    s.display = 'block';
    s.left = `${this.drag.x0 * 100}%`;
    s.top = `${this.drag.y0 * 100}%`;
    s.width = `${(this.drag.x1 - this.drag.x0) * 100}%`;
    s.height = `${(this.drag.y1 - this.drag.y0) * 100}%`;
  }

  // The dragged box in lon/lat: the image is linear in lon/lat over this.imageBox.
  lonlatBox() {
    const [w, s, e, n] = this.imageBox;
    const d = this.drag;
    return [w + d.x0 * (e - w), n - d.y1 * (n - s), w + d.x1 * (e - w), n - d.y0 * (n - s)];
  }

  bboxText() {
    return this.lonlatBox().map((v) => Number(v.toFixed(7))).join(',');
  }

  async showTin() {
    const faces = Math.round(Number(this.el.faces.value));
    const url = `/dems/${encodeURIComponent(this.dem.name)}/tin?bbox=${this.bboxText()}` +
        `&crs=EPSG:4326&faces=${faces}`;
    this.el.status.textContent = 'Loading the TIN…';
    this.el.status.classList.remove('error');
    try {
      const { blob, headers } = await getBlob(url);
      const origin = parseNumbers(headers.get('X-Tinbase-Origin'), 3);
      if (!origin) throw new ApiError(0, 'no_origin', 'the answer has no X-Tinbase-Origin header');
      const frame = Cesium.Transforms.eastNorthUpToFixedFrame(
          Cesium.Cartesian3.fromDegrees(origin[0], origin[1], origin[2]));
      const model = await Cesium.Model.fromGltfAsync({
        url: URL.createObjectURL(blob),
        modelMatrix: frame,
        color: Cesium.Color.ORANGE,
        colorBlendMode: Cesium.ColorBlendMode.MIX,
        colorBlendAmount: 0.35,
      });
      if (this.model) this.viewer.scene.primitives.remove(this.model);
      this.model = this.viewer.scene.primitives.add(model);
      this.outlineBox();
      this.loaded += 1;
      const at = origin.map((v) => v.toFixed(4)).join(', ');
      this.el.status.textContent = `TIN of ${faces} faces at ${at}`;
      this.el.status.dataset.loaded = String(this.loaded);
    } catch (e) {
      this.el.status.textContent = `Error: ${e.message}`;
      this.el.status.classList.add('error');
    }
  }

  outlineBox() {
    if (this.boxEntity) this.viewer.entities.remove(this.boxEntity);
    const [w, s, e, n] = this.lonlatBox();
    this.boxEntity = this.viewer.entities.add({
      polyline: {
        positions: Cesium.Cartesian3.fromDegreesArray([w, s, e, s, e, n, w, n, w, s]),
        clampToGround: true,
        width: 2,
        material: Cesium.Color.RED,
      },
    });
  }
}
