// Drawing a feature on the terrain: clicks add points, "Finish" posts it as GeoJSON in lon/lat
// (POST features?crs=EPSG:4326) with the chosen mode, tag and level and the typed token.
import * as Cesium from './cesium/index.js';
import { postJson, surfacePath } from './api.js';

export class FeatureDrawer {
  constructor(viewer, el) {
    this.viewer = viewer;
    this.el = el;  // {mode, tag, level, token, start, finish, cancel, status}
    this.points = null;  // lon/lat pairs while drawing, null otherwise
    this.entity = null;
    this.posted = 0;  // features posted so far (for tests)
    el.start.addEventListener('click', () => this.start());
    el.cancel.addEventListener('click', () => this.stop('Cancelled.'));
  }

  get drawing() {
    return this.points !== null;
  }

  start() {
    this.stop('Click points on the terrain, then finish.');
    this.points = [];
    const positions = new Cesium.CallbackProperty(() => {
      const ring = this.points.map(([lon, lat]) => Cesium.Cartesian3.fromDegrees(lon, lat));
      return ring.length > 2 && this.el.mode.value !== 'breakline' ? [...ring, ring[0]] : ring;
    }, false);
    this.entity = this.viewer.entities.add({
      polyline: { positions, clampToGround: true, width: 3, material: Cesium.Color.MAGENTA },
    });
    this.el.start.disabled = true;
    this.el.cancel.disabled = false;
    this.el.finish.disabled = true;
  }

  stop(message) {
    if (this.entity) this.viewer.entities.remove(this.entity);
    this.entity = null;
    this.points = null;
    this.el.start.disabled = false;
    this.el.finish.disabled = true;
    this.el.cancel.disabled = true;
    this.setStatus(message);
  }

  setStatus(message, error = false) {
    this.el.status.textContent = message;
    this.el.status.classList.toggle('error', error);
  }

  add(lonlat) {
    this.points.push([lonlat.lon, lonlat.lat]);
    const enough = this.points.length >= (this.el.mode.value === 'breakline' ? 2 : 3);
    this.el.finish.disabled = !enough;
    this.setStatus(`${this.points.length} point(s).`);
  }

  // The drawn shape as a GeoJSON Feature: a LineString for a breakline, a Polygon otherwise.
  feature() {
    const mode = this.el.mode.value;
    const properties = { mode, tag: this.el.tag.value.trim() || null };
    if (this.el.level.value !== '') properties.level = Number(this.el.level.value);
    const geometry = mode === 'breakline'
      ? { type: 'LineString', coordinates: this.points }
      : { type: 'Polygon', coordinates: [[...this.points, this.points[0]]] };
    return { type: 'Feature', geometry, properties };
  }

  // Posts the drawn feature to surface `name`; the change feed then redraws the view.
  async finish(name) {
    const feature = this.feature();
    this.el.finish.disabled = true;
    try {
      const answer = await postJson(surfacePath(name, 'features?crs=EPSG:4326'), feature,
          this.el.token.value, 'application/geo+json');
      this.posted += 1;
      this.stop(`Posted feature ${answer.features.join(', ')} (transaction ${answer.tx}).`);
      this.el.status.dataset.tx = String(answer.tx);
      return answer;
    } catch (e) {
      this.el.finish.disabled = false;
      this.setStatus(`Refused: ${e.message}`, true);
      return null;
    }
  }
}
