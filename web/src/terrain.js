// The globe: our quantized-mesh tiles as terrain (no Cesium ion, no imagery from the network),
// the DEM's hillshade overview draped as a single image when one covers the surface.
import * as Cesium from './cesium/index.js';
import { getBlob, getJson, parseNumbers, surfacePath } from './api.js';

// A Cesium viewer in `container` with nothing that reaches outside this server.
export function createViewer(container) {
  const viewer = new Cesium.Viewer(container, {
    baseLayer: false,
    baseLayerPicker: false,
    geocoder: false,
    homeButton: false,
    sceneModePicker: false,
    navigationHelpButton: false,
    animation: false,
    timeline: false,
    fullscreenButton: false,
    infoBox: false,
    selectionIndicator: false,
    requestRenderMode: false,
    // No stars or sky haze: where no tile is drawn the view stays plain black.
    skyBox: false,
    skyAtmosphere: false,
  });
  const globe = viewer.scene.globe;
  globe.baseColor = Cesium.Color.fromCssColorString('#b9ad94');
  globe.depthTestAgainstTerrain = false;
  // Lighting shows the relief when no hillshade is draped.
  globe.enableLighting = true;
  viewer.scene.light = new Cesium.DirectionalLight({
    direction: new Cesium.Cartesian3(0.4, 0.6, -0.7),
  });
  return viewer;
}

// Points the globe at surface `name`'s tiles. A new provider forgets every loaded tile, so after
// an edit the tiles are fetched again (the server's ETags keep unchanged ones cheap).
export async function loadTerrain(viewer, name) {
  // Cesium draws no globe at all (and says nothing) when the pyramid lists no root tile; the
  // service fills the levels above a small surface with flat tiles, so this is a broken pyramid.
  const layer = await getJson(surfacePath(name, 'tiles/layer.json'));
  const roots = Array.isArray(layer.available) ? layer.available[0] : null;
  if (!Array.isArray(roots) || roots.length === 0) {
    throw new Error(`the tiles of surface '${name}' have no level-0 tile: Cesium cannot show them`);
  }
  const provider = await Cesium.CesiumTerrainProvider.fromUrl(surfacePath(name, 'tiles/'), {
    requestVertexNormals: true,
  });
  viewer.scene.terrainProvider = provider;
  return provider;
}

// Drapes DEM `dem`'s overview (a hillshade) over the globe; returns the layer, or null when the
// server gives no placement for the image.
export async function drapeOverview(viewer, dem) {
  const { blob, headers } = await getBlob(`/dems/${encodeURIComponent(dem.name)}/overview.png`);
  const bbox = parseNumbers(headers.get('X-Tinbase-Bbox-Lonlat'), 4) || dem.bbox_lonlat;
  if (!bbox) return null;
  const provider = await Cesium.SingleTileImageryProvider.fromUrl(URL.createObjectURL(blob), {
    rectangle: Cesium.Rectangle.fromDegrees(...bbox),
  });
  return viewer.imageryLayers.addImageryProvider(provider);
}

// The lon/lat (degrees) of the globe under window position `position`, or null.
export function pickLonLat(viewer, position) {
  const ray = viewer.camera.getPickRay(position);
  // Where no terrain tile is drawn (outside the surface), the ellipsoid stands in.
  const point = (ray && viewer.scene.globe.pick(ray, viewer.scene)) ||
      viewer.camera.pickEllipsoid(position, viewer.scene.globe.ellipsoid);
  if (!point) return null;
  const c = Cesium.Cartographic.fromCartesian(point);
  return { lon: Cesium.Math.toDegrees(c.longitude), lat: Cesium.Math.toDegrees(c.latitude) };
}

// Whether the lon/lat boxes [w,s,e,n] `a` and `b` overlap.
export function boxesOverlap(a, b) {
  return a[0] <= b[2] && b[0] <= a[2] && a[1] <= b[3] && b[1] <= a[3];
}
