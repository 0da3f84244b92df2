// Triangles two reference meshers need for a height field at given vertical errors (metres):
// delatin (greedy Delaunay insertion until every sample is within the error: the same exact
// bound terralod's levels hold) and @mapbox/martini (RTIN, errors measured at triangle
// midpoints only; needs a square grid of 2^k + 1 samples). Both are npm packages pinned in
// tests/tools, used here as yardsticks, not by terralod.
//
// node bench/triangles_per_error.mjs HEIGHTS.f32 WIDTH HEIGHT ERROR... prints one JSON object:
// {"delatin": [...], "martini": [...]} (martini null where the grid does not suit it), one count
// per error, in the order given.

import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';

const tools = fileURLToPath(new URL('../tests/tools/', import.meta.url));
const require = createRequire(tools);
const { default: Delatin } = await import(tools + 'node_modules/delatin/index.js');
const Martini = require('@mapbox/martini');

const [file, w, h, ...errorArgs] = process.argv.slice(2);
const width = Number(w), height = Number(h);
const errors = errorArgs.map(Number);
const bytes = readFileSync(file);
const heights = new Float32Array(bytes.buffer, bytes.byteOffset, width * height);

// Delatin refines as far as asked and can go on: coarsest error first.
const order = errors.map((e, i) => [e, i]).sort((a, b) => b[0] - a[0]);
const delatin = new Array(errors.length);
const tin = new Delatin(heights, width, height);
for (const [e, i] of order) {
  tin.run(e);
  delatin[i] = tin.triangles.length / 3;
  process.stderr.write(`delatin: error ${e} m: ${delatin[i]} triangles\n`);
}

const size = width - 1;
const martini = errors.map(() => null);
if (width === height && size > 0 && (size & (size - 1)) === 0) {
  const tile = new Martini(width).createTile(heights);
  for (const [e, i] of order) {
    martini[i] = tile.getMesh(e).triangles.length / 3;
    process.stderr.write(`martini: error ${e} m: ${martini[i]} triangles\n`);
  }
}
console.log(JSON.stringify({ delatin, martini }));
