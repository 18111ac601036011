// One colour per feature tag, the same on every load (a hash of the tag picks the hue), so the
// legend and the drawn features agree without a shared table.
import * as Cesium from './cesium/index.js';

const UNTAGGED = '#808080';

// The CSS colour of `tag` (null or empty: grey).
export function tagCss(tag) {
  if (!tag) return UNTAGGED;
  let hash = 2166136261;
  for (let i = 0; i < tag.length; i++) {
    hash ^= tag.charCodeAt(i);
    hash = Math.imul(hash, 16777619) >>> 0;
  }
  // The golden-angle step spreads hues of similar hashes apart.
  const hue = (hash % 360 + (hash >>> 9) * 137.508) % 360;
  return `hsl(${hue.toFixed(0)}, 75%, 50%)`;
}

// The Cesium colour of `tag` with `alpha`.
export function tagColor(tag, alpha = 1) {
  return Cesium.Color.fromCssColorString(tagCss(tag)).withAlpha(alpha);
}
