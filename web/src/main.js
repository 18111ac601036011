// The viewer's entry point: picks the surface, then wires the globe, the features and legend,
// the click panel, the DEM overview, drawing and the change feed together. window.tinbase
// exposes the parts to the browser tests (tests/browser).
import * as Cesium from './cesium/index.js';
import { getJson } from './api.js';
import { FeatureDrawer } from './draw.js';
import { loadFeatures, showLegend } from './features.js';
import { followChanges } from './live.js';
import { OverviewMap } from './overview.js';
import { TrianglePicker } from './pick.js';
import { boxesOverlap, createViewer, drapeOverview, loadTerrain, pickLonLat } from './terrain.js';

const $ = (id) => document.getElementById(id);

const state = {
  surface: null,       // the surface shown (an entry of GET /surfaces)
  features: null,      // {source, geojson} of the drawn features
  featureLoads: 0,     // times the features were (re)loaded
  terrainLoads: 0,     // times the terrain provider was (re)made
  changes: [],         // change events received
  errors: [],          // messages shown in the status line
};

function setStatus(message, error = false) {
  $('status').textContent = message;
  $('status').classList.toggle('error', error);
  if (error) state.errors.push(message);
}

async function reloadFeatures(viewer) {
  const name = state.surface.name;
  state.features = await loadFeatures(viewer, name, state.features && state.features.source);
  await showLegend($('legend'), name, state.features.geojson);
  state.featureLoads += 1;
}

async function reloadTerrain(viewer) {
  await loadTerrain(viewer, state.surface.name);
  state.terrainLoads += 1;
}

// The surface named by ?surface=, else the first one with tiles, else the first.
function chooseSurface(surfaces) {
  const wanted = new URLSearchParams(location.search).get('surface');
  return surfaces.find((s) => s.name === wanted) ||
      surfaces.find((s) => Array.isArray(s.tiles) && s.tiles.length > 0) || surfaces[0];
}

// The surface's lon/lat box: from the service, or its extent when the store is in lon/lat.
function lonLatExtent(surface) {
  if (surface.extent_lonlat) return surface.extent_lonlat;
  const e = surface.extent;
  if (e && /EPSG:?4326|WGS ?84/i.test(String(surface.crs))) return [e[0], e[1], e[3], e[4]];
  return null;
}

function lookAt(viewer, extent) {
  if (!extent) return;
  viewer.camera.setView({ destination: Cesium.Rectangle.fromDegrees(...extent) });
}

async function setupOverview(viewer, overview) {
  const { dems } = await getJson('/dems');
  const select = $('dem');
  for (const d of dems) select.add(new Option(d.name, d.name));
  const byName = (name) => dems.find((d) => d.name === name);
  select.addEventListener('change', () => overview.show(byName(select.value)));
  if (dems.length > 0) await overview.show(dems[0]);
  // The hillshade of the DEM under the surface, as the globe's only imagery.
  const extent = lonLatExtent(state.surface);
  const under = dems.find((d) => d.bbox_lonlat && extent && boxesOverlap(d.bbox_lonlat, extent));
  if (under) await drapeOverview(viewer, under);
}

function setupClicks(viewer, picker, drawer) {
  const handler = new Cesium.ScreenSpaceEventHandler(viewer.scene.canvas);
  handler.setInputAction((click) => {
    const lonlat = pickLonLat(viewer, click.position);
    if (!lonlat) return;
    if (drawer.drawing) drawer.add(lonlat);
    else picker.pick(state.surface.name, lonlat);
  }, Cesium.ScreenSpaceEventType.LEFT_CLICK);
  $('draw-finish').addEventListener('click', () => drawer.finish(state.surface.name));
}

// Redraws after an edit: soon, and once for a burst of changes.
function onChangeReload(viewer) {
  let timer = null;
  return (change) => {
    state.changes.push(change);
    const item = document.createElement('li');
    item.textContent = `tx ${change.tx}: ${change.action ?? 'edit'}` +
        (change.feature != null ? ` of feature ${change.feature}` : '');
    $('changes').prepend(item);
    clearTimeout(timer);
    timer = setTimeout(async () => {
      try {
        await Promise.all([reloadTerrain(viewer), reloadFeatures(viewer)]);
        setStatus(`Updated to transaction ${change.tx}.`);
      } catch (e) {
        setStatus(`Could not redraw after transaction ${change.tx}: ${e.message}`, true);
      }
    }, 200);
  };
}

async function main() {
  const viewer = createViewer($('globe'));
  const picker = new TrianglePicker(viewer, $('pick'));
  const drawer = new FeatureDrawer(viewer, {
    mode: $('draw-mode'), tag: $('draw-tag'), level: $('draw-level'), token: $('draw-token'),
    start: $('draw-start'), finish: $('draw-finish'), cancel: $('draw-cancel'),
    status: $('draw-status'),
  });
  const overview = new OverviewMap(viewer, {
    image: $('overview-image'), box: $('overview-box'), frame: $('overview'), faces: $('faces'),
    button: $('show-tin'), status: $('tin-status'),
  });
  window.tinbase = { Cesium, viewer, state, picker, drawer, overview };
  $('terrain-on').addEventListener('change', (e) => {
    viewer.scene.globe.show = e.target.checked;
  });

  const { surfaces } = await getJson('/surfaces');
  if (surfaces.length === 0) {
    setStatus('The store has no surface yet.');
    return;
  }
  for (const s of surfaces) $('surface').add(new Option(s.name, s.name));
  state.surface = chooseSurface(surfaces);
  $('surface').value = state.surface.name;
  $('surface').addEventListener('change', () => {
    location.search = `?surface=${encodeURIComponent($('surface').value)}`;
  });
  lookAt(viewer, lonLatExtent(state.surface));
  setupClicks(viewer, picker, drawer);
  await reloadTerrain(viewer);
  // Each part is drawn on its own, so one failing route leaves the others working.
  await reloadFeatures(viewer).catch((e) => {
    $('legend').textContent = `The features could not be loaded: ${e.message}`;
  });
  await followChanges(onChangeReload(viewer), (e) => setStatus(e.message, true));
  setStatus(`Surface ${state.surface.name}: ${state.surface.triangles} triangles.`);
  document.body.dataset.ready = 'true';
  // The overview is extra: a store without DEMs (or a failing route) leaves the rest working.
  setupOverview(viewer, overview).catch((e) => {
    $('tin-status').textContent = `Error: ${e.message}`;
  });
}

main().catch((e) => setStatus(`The viewer could not start: ${e.message}`, true));
