// Decodes quantized-mesh tiles with @here/quantized-mesh-decoder (a reader tinbase did not
// write) and prints, per file, what it read as one JSON object: counts, header, vertices,
// indices, edge lists and extensions. Usage: node decode_terrain.mjs FILE...
// A gzipped tile is gunzipped first, as a browser would on Content-Encoding: gzip.
import pkg from '@here/quantized-mesh-decoder'
import fs from 'fs'
import zlib from 'zlib'

const decode = pkg.default || pkg
const out = {}
for (const file of process.argv.slice(2)) {
  let buf = fs.readFileSync(file)
  if (buf[0] === 0x1f && buf[1] === 0x8b) buf = zlib.gunzipSync(buf)
  const r = decode(buf.buffer.slice(buf.byteOffset, buf.byteOffset + buf.byteLength))
  const n = r.vertexData.length / 3
  out[file] = {
    vertices: n,
    triangles: r.triangleIndices.length / 3,
    header: r.header,
    u: Array.from(r.vertexData.subarray(0, n)),
    v: Array.from(r.vertexData.subarray(n, 2 * n)),
    height: Array.from(r.vertexData.subarray(2 * n)),
    indices: Array.from(r.triangleIndices),
    west: Array.from(r.westIndices),
    south: Array.from(r.southIndices),
    east: Array.from(r.eastIndices),
    north: Array.from(r.northIndices),
    normals: r.extensions.vertexNormals ? Array.from(r.extensions.vertexNormals) : null,
    waterMask: r.extensions.waterMask ? Array.from(new Uint8Array(r.extensions.waterMask)) : null,
    metadata: r.extensions.metadata || null
  }
}
process.stdout.write(JSON.stringify(out))
