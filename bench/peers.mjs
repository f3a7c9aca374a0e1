// One run of an npm Poisson-disk sampler for bench/peers: node peers.mjs MODULE_DIR NAME R SEED OUT.csv
// Samples the unit square (free boundary) at minimum distance R with a seeded generator, writes
// the points as CSV with an x,y header, and prints the seconds fill() took.
import { createRequire } from 'node:module';
import { writeFileSync } from 'node:fs';
import path from 'node:path';

const [moduleDir, name, radiusText, seedText, out] = process.argv.slice(2);
const require = createRequire(path.join(moduleDir, 'index.js'));
const r = Number(radiusText);

// mulberry32: a small seeded generator, so that runs repeat.
function mulberry32(seed) {
  let a = seed >>> 0;
  return () => {
    a = (a + 0x6d2b79f5) >>> 0;
    let t = a;
    t = Math.imul(t ^ (t >>> 15), t | 1);
    t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
}
const rng = mulberry32(Number(seedText) + 1);

let sampler;
if (name === 'poisson-disk-sampling') {
  const PoissonDiskSampling = require('poisson-disk-sampling');
  sampler = new PoissonDiskSampling({ shape: [1, 1], minDistance: r, maxDistance: 2 * r, tries: 30 }, rng);
} else if (name === 'fast-2d-poisson-disk-sampling') {
  const FastPoissonDiskSampling = require('fast-2d-poisson-disk-sampling');
  sampler = new FastPoissonDiskSampling({ shape: [1, 1], radius: r, tries: 30 }, rng);
} else {
  throw new Error(`unknown sampler ${name}`);
}
const start = process.hrtime.bigint();
const points = sampler.fill();
const seconds = Number(process.hrtime.bigint() - start) / 1e9;
const rows = ['x,y'];
for (const p of points) if (p[0] < 1 && p[1] < 1) rows.push(`${p[0]},${p[1]}`);
writeFileSync(out, rows.join('\n') + '\n');
console.log(seconds.toFixed(6));
