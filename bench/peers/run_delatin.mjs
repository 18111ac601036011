// Runs npm delatin once on a terrain written by `dense_bench export`, to one max error, and writes
// its mesh for dense_bench to score: the whole process is what scripts/bench-dense.sh times, as
// it times hmm and `tinbase tin build`.
//
// Usage: node run_delatin.mjs TERRAIN.f32 WIDTH HEIGHT MAX_ERROR OUT.mesh
// OUT.mesh: u32 vertex count, u32 triangle count, u32 x,y per vertex in grid cells, u32 a,b,c per
// triangle.
import fs from 'node:fs';
import Delatin from 'delatin';

const [file, widthText, heightText, errorText, outPath] = process.argv.slice(2);
const width = Number(widthText), height = Number(heightText);
const bytes = fs.readFileSync(file);
const data = new Float32Array(bytes.buffer, bytes.byteOffset, width * height);
const tin = new Delatin(data, width, height);
tin.run(Number(errorText));
const coords = Uint32Array.from(tin.coords);
const out = new Uint32Array(2 + coords.length + tin.triangles.length);
out[0] = coords.length / 2;
out[1] = tin.triangles.length / 3;
out.set(coords, 2);
out.set(tin.triangles, 2 + coords.length);
fs.writeFileSync(outPath, Buffer.from(out.buffer));
