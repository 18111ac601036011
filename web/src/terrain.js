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

// Our tiles as Cesium sees them, with flat stand-ins (the ellipsoid, height 0) at the levels
// coarser than the pyramid's first one. A pyramid starts at the first level where the surface has
// a tile, but Cesium draws no globe without the two root tiles, keeps no availability at all when
// layer.json lists none at level 0, and stops refining below a level it would have to upsample
// whole. So the availability is rebuilt here from layer.json with the root levels added.
class SurfaceTerrainProvider {
  constructor(tiles, available) {
    this.tiles = tiles;
    this.flat = new Cesium.EllipsoidTerrainProvider({ tilingScheme: tiles.tilingScheme });
    const scheme = tiles.tilingScheme;
    this.firstLevel = Math.max(0, available.findIndex((r) => Array.isArray(r) && r.length > 0));
    this.ownAvailability = new Cesium.TileAvailability(scheme, Math.max(available.length, 1));
    for (let level = 0; level < this.firstLevel; level++) {
      this.ownAvailability.addAvailableTileRange(level, 0, 0,
          scheme.getNumberOfXTilesAtLevel(level) - 1, scheme.getNumberOfYTilesAtLevel(level) - 1);
    }
    for (let level = this.firstLevel; level < available.length; level++) {
      // layer.json counts y from the south (TMS); Cesium counts from the north.
      const rows = scheme.getNumberOfYTilesAtLevel(level);
      for (const r of available[level] || []) {
        this.ownAvailability.addAvailableTileRange(level, r.startX, rows - 1 - r.endY, r.endX,
            rows - 1 - r.startY);
      }
    }
  }

  get errorEvent() { return this.tiles.errorEvent; }
  get credit() { return this.tiles.credit; }
  get tilingScheme() { return this.tiles.tilingScheme; }
  get hasWaterMask() { return this.tiles.hasWaterMask; }
  get hasVertexNormals() { return this.tiles.hasVertexNormals; }
  get availability() { return this.ownAvailability; }

  requestTileGeometry(x, y, level, request) {
    if (level < this.firstLevel) return this.flat.requestTileGeometry(x, y, level, request);
    return this.tiles.requestTileGeometry(x, y, level, request);
  }

  getLevelMaximumGeometricError(level) { return this.tiles.getLevelMaximumGeometricError(level); }

  getTileDataAvailable(x, y, level) { return this.ownAvailability.isTileAvailable(level, x, y); }

  loadTileDataAvailability() { return undefined; }
}

// Points the globe at surface `name`'s tiles. A new provider forgets every loaded tile, so after
// an edit the tiles are fetched again (the server's ETags keep unchanged ones cheap).
export async function loadTerrain(viewer, name) {
  const tiles = await Cesium.CesiumTerrainProvider.fromUrl(surfacePath(name, 'tiles/'), {
    requestVertexNormals: true,
  });
  const layer = await getJson(surfacePath(name, 'tiles/layer.json'));
  const available = Array.isArray(layer.available) ? layer.available : [];
  const provider = new SurfaceTerrainProvider(tiles, available);
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
