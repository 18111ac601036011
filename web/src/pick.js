// A click on the terrain: the triangle under it (GET locate), its z and tag in the panel, and the
// triangle with its neighbours (GET triangles/{id}) outlined on the ground.
import * as Cesium from './cesium/index.js';
import { getJson, surfacePath } from './api.js';

// The triangle's corners as Cartesian3, from its lon/lat/height vertices.
function corners(triangle) {
  return triangle.lonlat.map(([lon, lat, h]) => Cesium.Cartesian3.fromDegrees(lon, lat, h));
}

function outline(triangle, color, width) {
  const ring = corners(triangle);
  return new Cesium.Entity({
    polyline: { positions: [...ring, ring[0]], clampToGround: true, width, material: color },
  });
}

function row(table, label, value) {
  const tr = table.insertRow();
  tr.insertCell().textContent = label;
  const cell = tr.insertCell();
  cell.textContent = value;
  return cell;
}

export class TrianglePicker {
  constructor(viewer, panel) {
    this.viewer = viewer;
    this.panel = panel;
    this.entities = [];
    this.last = null;  // the last located answer (for tests and the status line)
  }

  clear() {
    for (const e of this.entities) this.viewer.entities.remove(e);
    this.entities = [];
  }

  // Locates lon/lat on surface `name`, fills the panel and highlights the triangles.
  async pick(name, lonlat) {
    this.clear();
    const at = `lon=${lonlat.lon.toFixed(7)}&lat=${lonlat.lat.toFixed(7)}`;
    let located;
    try {
      located = await getJson(surfacePath(name, `locate?${at}`));
    } catch (e) {
      this.last = { error: e.code || 'error' };
      this.panel.dataset.state = 'error';
      this.panel.textContent =
          e.code === 'outside' ? 'Outside the surface.' : `Error: ${e.message}`;
      return;
    }
    const t = located.triangle;
    this.last = located;
    const table = document.createElement('table');
    row(table, 'triangle', String(t.id)).id = 'pick-triangle';
    row(table, 'z', Number(located.z).toFixed(2)).id = 'pick-z';
    row(table, 'tag', t.tag ?? '(none)').id = 'pick-tag';
    row(table, 'lon, lat', `${lonlat.lon.toFixed(5)}, ${lonlat.lat.toFixed(5)}`);
    row(table, 'neighbours', t.neighbours.map((n) => n ?? '–').join(', '));
    this.panel.replaceChildren(table);
    this.panel.dataset.state = 'located';
    this.panel.dataset.triangle = String(t.id);
    await this.highlight(name, t.id);
  }

  async highlight(name, id) {
    let answer;
    try {
      answer = await getJson(surfacePath(name, `triangles/${id}`));
    } catch (e) {
      return;  // the panel already shows the triangle; only the outline is missing
    }
    const shown = [outline(answer.triangle, Cesium.Color.YELLOW, 4)];
    // Invisible neighbours (clipped or erased) are not part of the drawn surface.
    for (const n of answer.neighbours) {
      if (n && n.visible !== false) shown.push(outline(n, Cesium.Color.CYAN, 2));
    }
    const ring = corners(answer.triangle);
    shown.push(new Cesium.Entity({
      polygon: {
        hierarchy: ring,
        material: Cesium.Color.YELLOW.withAlpha(0.5),
        classificationType: Cesium.ClassificationType.TERRAIN,
      },
    }));
    for (const e of shown) this.viewer.entities.add(e);
    this.entities = shown;
    this.panel.dataset.highlighted = String(shown.length - 1);
  }
}
