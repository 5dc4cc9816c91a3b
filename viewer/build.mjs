// Builds the viewer into static files: OUT/index.html, OUT/viewer.js (three.js bundled in, no CDN),
// OUT/viewer.css. Usage: node build.mjs OUT (scripts/build_viewer.sh runs it after `npm ci`).
import { build } from 'esbuild';
import { copyFileSync, mkdirSync } from 'node:fs';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const out = resolve(process.argv[2] ?? join(here, '..', 'build', 'viewer'));
mkdirSync(out, { recursive: true });
await build({
  entryPoints: [join(here, 'src', 'main.js')],
  bundle: true,
  format: 'iife',
  target: 'chrome100',
  minify: true,
  legalComments: 'eof', // three.js's licence notice stays in the bundle
  outfile: join(out, 'viewer.js'),
  logLevel: 'warning',
});
copyFileSync(join(here, 'index.html'), join(out, 'index.html'));
copyFileSync(join(here, 'src', 'viewer.css'), join(out, 'viewer.css'));
console.log(`viewer built into ${out}`);
