// Runs npm delatin (greedy insertion, Garland-Heckbert) and @mapbox/martini (RTIN) on a terrain
// written by `tin_bench export`, at each max error, and writes every mesh so tin_bench measures its
// true error with the same code as tinbase's own results.
//
// Usage: node run_peers.mjs TERRAIN.f32 WIDTH HEIGHT OUTDIR ERR1,ERR2,...
// Writes OUTDIR/<peer>_<err>.mesh (u32 vertex count, u32 triangle count, u32 x,y per vertex in grid
// cells, u32 a,b,c per triangle) and prints one JSON line per run: {peer, error, seconds, ...}.
import fs from 'node:fs';
import path from 'node:path';
import Delatin from 'delatin';
import Martini from '@mapbox/martini';

const [file, widthText, heightText, outDir, errorsText] = process.argv.slice(2);
const width = Number(widthText), height = Number(heightText);
const bytes = fs.readFileSync(file);
const data = new Float32Array(bytes.buffer, bytes.byteOffset, width * height);
const errors = errorsText.split(',').map(Number);

function writeMesh(name, coords, triangles) {
  const vertices = coords.length / 2;
  const out = new Uint32Array(2 + coords.length + triangles.length);
  out[0] = vertices;
  out[1] = triangles.length / 3;
  out.set(coords, 2);
  out.set(triangles, 2 + coords.length);
  fs.writeFileSync(path.join(outDir, name), Buffer.from(out.buffer));
}

// Best of `runs` timings of fn (after one warm-up run, so the JIT has compiled it).
function time(fn, runs) {
  let result = fn();
  let best = Infinity;
  for (let i = 0; i < runs; i++) {
    const start = process.hrtime.bigint();
    result = fn();
    best = Math.min(best, Number(process.hrtime.bigint() - start) / 1e9);
  }
  return { result, best };
}

const runs = width * height > 5e6 ? 1 : 3;
for (const maxError of errors) {
  const d = time(() => {
    const tin = new Delatin(data, width, height);
    tin.run(maxError);
    return tin;
  }, runs);
  writeMesh(`delatin_${maxError}.mesh`, Uint32Array.from(d.result.coords), d.result.triangles);
  console.log(JSON.stringify({ peer: 'delatin', error: maxError, seconds: d.best,
                               triangles: d.result.triangles.length / 3,
                               reported_max_error: d.result.getMaxError() }));
}

// martini wants a square (2^k + 1)^2 grid.
const size = width;
if (width === height && ((size - 1) & (size - 2)) === 0) {
  for (const maxError of errors) {
    const m = time(() => {
      const martini = new Martini(size);
      return martini.createTile(data).getMesh(maxError);
    }, runs);
    writeMesh(`martini_${maxError}.mesh`, Uint32Array.from(m.result.vertices), m.result.triangles);
    console.log(JSON.stringify({ peer: 'martini', error: maxError, seconds: m.best,
                                 triangles: m.result.triangles.length / 3 }));
  }
}
