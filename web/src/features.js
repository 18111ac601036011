// The surface's features drawn on the ground, coloured by tag, with the legend beside the globe.
import * as Cesium from './cesium/index.js';
import { getJson, surfacePath } from './api.js';
import { tagColor, tagCss } from './colors.js';

// Colours every entity of `source` by its feature's tag: areas half transparent on the ground,
// lines (breaklines) opaque.
function colourByTag(source) {
  for (const entity of source.entities.values) {
    const p = entity.properties;
    const tag = p && p.tag ? p.tag.getValue() : null;
    if (entity.polygon) {
      entity.polygon.material = tagColor(tag, 0.45);
      entity.polygon.outline = false;
      // A ground outline, since polygon outlines are not drawn on terrain.
      const ring = entity.polygon.hierarchy.getValue(Cesium.JulianDate.now()).positions;
      entity.polyline = new Cesium.PolylineGraphics({
        positions: [...ring, ring[0]],
        clampToGround: true,
        width: 2,
        material: tagColor(tag, 1),
      });
    }
    if (entity.polyline && !entity.polygon) {
      entity.polyline.material = tagColor(tag, 1);
      entity.polyline.width = 3;
    }
  }
}

// Replaces the drawn features with the surface's current ones; returns their GeoJSON.
export async function loadFeatures(viewer, name, previous) {
  const geojson = await getJson(surfacePath(name, 'features?crs=EPSG:4326'));
  const source = await Cesium.GeoJsonDataSource.load(geojson, { clampToGround: true });
  colourByTag(source);
  await viewer.dataSources.add(source);
  if (previous) viewer.dataSources.remove(previous, true);
  return { source, geojson };
}

// The legend: one line per tag with its colour and, when the server counts them, its triangles.
export async function showLegend(list, name, geojson) {
  const counts = new Map();
  for (const f of geojson.features || []) {
    const tag = (f.properties && f.properties.tag) || null;
    counts.set(tag, { features: ((counts.get(tag) || {}).features || 0) + 1 });
  }
  try {
    const { tags } = await getJson(surfacePath(name, 'tags'));
    for (const t of tags) {
      counts.set(t.tag, { ...(counts.get(t.tag) || {}), triangles: t.triangles });
    }
  } catch (e) {
    // The tag counts are extra: the features alone still make a legend.
  }
  list.replaceChildren();
  const keys = [...counts.keys()].sort((a, b) => String(a).localeCompare(String(b)));
  for (const tag of keys) {
    const { features, triangles } = counts.get(tag);
    const item = document.createElement('li');
    item.dataset.tag = tag ?? '';
    const swatch = document.createElement('span');
    swatch.className = 'swatch';
    swatch.style.background = tagCss(tag);
    const parts = [];
    if (features) parts.push(`${features} feature${features === 1 ? '' : 's'}`);
    if (triangles !== undefined) parts.push(`${triangles} triangles`);
    item.append(swatch, `${tag ?? '(no tag)'}: ${parts.join(', ')}`);
    list.append(item);
  }
  if (keys.length === 0) list.textContent = 'No features yet.';
}
