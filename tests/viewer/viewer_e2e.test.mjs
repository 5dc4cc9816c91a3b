// End-to-end test of the web viewer (docs/viewer.md) in headless Chromium: a short recorded run is
// served by `rbpart view` and played (the step counter advances), part colours reach the screen
// (pixels of a screenshot sampled against the palette), malformed recordings show an error message
// instead of a blank page, and `rbpart snapshot` writes the picture of a step, framed on the
// dynamic bodies from the direction its camera options give.
// Run by CTest (CMakeLists.txt) with RBPART_CLI and RBPART_VIEWER_DIR set.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { spawn, spawnSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { Browser, CHROMIUM, decodePng, paletteCounts, paletteExtent } from './chromium.mjs';
import { PALETTE } from '../../viewer/src/colouring.js';

const CLI = process.env.RBPART_CLI;
const VIEWER = process.env.RBPART_VIEWER_DIR;
const STEPS = 45;

let dir, browser, recording, garbage, truncated;

function rbpart(args, env = {}) {
  const r = spawnSync(CLI, args, { cwd: dir, encoding: 'utf8', env: { ...process.env, ...env }, timeout: 120000 });
  return { status: r.status, stdout: r.stdout, stderr: r.stderr };
}

before(async () => {
  assert.ok(CLI && existsSync(CLI), `RBPART_CLI (${CLI}) is the rbpart binary`);
  assert.ok(VIEWER && existsSync(join(VIEWER, 'viewer.js')),
    `the viewer is built in RBPART_VIEWER_DIR (${VIEWER}): run scripts/build_viewer.sh`);
  assert.ok(existsSync(CHROMIUM), `${CHROMIUM} exists (Debian's chromium; scripts/install_deps.sh installs it)`);
  dir = mkdtempSync(join(tmpdir(), 'rbpart-viewer-test-'));
  // 20 rocks land in the bin within these steps; nmax 4 makes the recorder's BFS parts small, so
  // that parts touch and interface edges exist.
  const run = rbpart(['simulate', '--scene', 'rock_pile', '--set', 'rocks=20', '--steps', String(STEPS),
    '--nmax', '4', '--record', 'r.rbrec', '--record-partitioners', 'bfs', '-q']);
  assert.equal(run.status, 0, run.stderr);
  recording = join(dir, 'r.rbrec');
  garbage = join(dir, 'garbage.rbrec');
  writeFileSync(garbage, 'this is not a recording\n');
  truncated = join(dir, 'truncated.rbrec');
  const bytes = readFileSync(recording);
  writeFileSync(truncated, bytes.subarray(0, bytes.length >> 1));
  browser = await Browser.launch();
});

after(async () => {
  if (browser) await browser.close();
  if (dir) rmSync(dir, { recursive: true, force: true });
});

const frameOf = "Number(document.getElementById('frame').dataset.frame)";
const statOf = (key) => `document.querySelector('#stats tr[data-key="${key}"] td')?.textContent`;

test('rbpart view serves the viewer, which plays the recording', { timeout: 60000 }, async () => {
  const server = spawn(CLI, ['view', recording, '--port', '0'], { stdio: ['ignore', 'pipe', 'pipe'] });
  try {
    const url = await new Promise((resolve, reject) => {
      let out = '';
      server.stdout.on('data', (d) => {
        out += d;
        const m = out.match(/http:\/\/127\.0\.0\.1:\d+\/\S*/);
        if (m) resolve(m[0]);
      });
      server.on('exit', (code) => reject(new Error(`rbpart view exited (${code}): ${out}`)));
    });
    const page = await browser.newPage(1200, 800);
    await page.goto(url);
    await page.waitFor(`${frameOf} >= 0`, 'the first frame');
    const first = await page.evaluate(frameOf);
    // Playing at 1x, a 60 Hz recording advances about one frame per 17 ms.
    const later = await page.waitFor(`${frameOf} !== ${first} && ${frameOf}`, 'the frame counter to advance');
    assert.notEqual(later, first);
    assert.match(await page.evaluate("document.getElementById('frame').textContent"), new RegExp(`^step \\d+ / ${STEPS}$`));
    assert.deepEqual(await page.evaluate("[...document.getElementById('channel').options].map((o) => o.text)"),
      ['islands', 'bfs']);
    assert.match(await page.evaluate(statOf('parts')), /^\d+$/);
    assert.equal(await page.evaluate("document.getElementById('error').hidden"), true);
    assert.deepEqual(page.exceptions, []);
  } finally {
    server.kill();
  }
  // A file that is not a recording is refused before anything is served.
  const bad = rbpart(['view', garbage, '--port', '0']);
  assert.equal(bad.status, 2);
  assert.match(bad.stderr, /not an rbpart recording/);
});

test('part colours reach the screen, and the graph overlay draws interface edges', { timeout: 60000 }, async () => {
  const html = rbpart(['view', recording, '--html', 'page.html']);
  assert.equal(html.status, 0, html.stderr);
  const page = await browser.newPage(1000, 700);
  // Unlit colours and no bin walls: every rock pixel is exactly its part's palette colour.
  await page.goto(`file://${join(dir, 'page.html')}#play=0&flat=1&statics=0&channel=bfs&step=${STEPS}`);
  await page.waitFor(`${frameOf} === ${STEPS - 1}`, `step ${STEPS}`);
  const parts = Number(await page.evaluate(statOf('parts')));
  const cut = Number(await page.evaluate(statOf('edge cut')));
  assert.ok(parts >= 3, `the BFS channel has at least 3 parts at step ${STEPS} (${parts})`);
  // Only the 3D view counts: the panel's legend shows every palette colour.
  const canvas = await page.evaluate(
    "(({ x, y, width, height }) => ({ x, y, width, height }))(document.getElementById('view').getBoundingClientRect())");
  const counts = paletteCounts(await page.screenshot(), PALETTE, 3, canvas);
  const shown = counts.filter((n) => n >= 20).length;
  assert.ok(shown >= 3, `at least 3 palette colours cover 20+ pixels each: ${counts}`);

  // The overlay: bold interface edges (colour 0x111111) exist where the partition cuts edges.
  assert.ok(cut > 0, 'the BFS parts share edges at this step');
  await page.evaluate("document.getElementById('graph').click()");
  const withGraph = await page.screenshot();
  const dark = paletteCounts(withGraph, [0x111111], 8, canvas)[0];
  assert.ok(dark > 30, `interface edges drawn (${dark} dark pixels)`);
  assert.deepEqual(page.exceptions, []);
});

test('malformed recordings show an error message, not a blank page', { timeout: 60000 }, async () => {
  const page = await browser.newPage(1000, 700);
  await page.goto(`file://${join(VIEWER, 'index.html')}`);
  assert.equal(await page.evaluate("document.getElementById('hint').hidden"), false);
  for (const [file, message] of [[garbage, 'not an rbpart recording'], [truncated, 'corrupt or truncated']]) {
    await page.setInputFile('#file', file);
    const text = await page.waitFor(
      "!document.getElementById('error').hidden && document.getElementById('error').textContent", 'the error message');
    assert.match(text, new RegExp(message), text);
    assert.match(text, /^Cannot open (garbage|truncated)\.rbrec: /);
    // The message is on screen: the error box's background covers many pixels.
    const box = paletteCounts(await page.screenshot(), [0xfde8e8], 2)[0];
    assert.ok(box > 5000, `error box visible (${box} pixels)`);
    await page.evaluate("document.getElementById('error').hidden = true");
  }
});

test('rbpart snapshot renders one step to PNG, and refuses bad input', { timeout: 60000 }, () => {
  const shot = rbpart(['snapshot', 'r.rbrec', '--step', String(STEPS), '--out', 'fig.png', '--width', '640',
    '--height', '400', '--channel', 'bfs', '--flat', '--hide-static']);
  assert.equal(shot.status, 0, shot.stderr);
  const image = decodePng(readFileSync(join(dir, 'fig.png')));
  assert.equal(image.width, 640);
  assert.equal(image.height, 400);
  const counts = paletteCounts(image, PALETTE);
  assert.ok(counts.filter((n) => n >= 10).length >= 3, `palette colours in the snapshot: ${counts}`);

  const bad = rbpart(['snapshot', 'garbage.rbrec', '--step', '1', '--out', 'bad.png']);
  assert.equal(bad.status, 2);
  assert.match(bad.stderr, /garbage\.rbrec: not an rbpart recording/);
  const step = rbpart(['snapshot', 'r.rbrec', '--step', '999', '--out', 'bad.png']);
  assert.equal(step.status, 2);
  assert.match(step.stderr, /no step 999 \(it holds steps 1 to 45\)/);
  const missing = rbpart(['snapshot', 'r.rbrec', '--step', '1', '--out', 'bad.png'], { RBPART_CHROMIUM: join(dir, 'none') });
  assert.equal(missing.status, 2);
  assert.match(missing.stderr, /RBPART_CHROMIUM=.* is not an executable/);
  const nochromium = rbpart(['snapshot', 'r.rbrec', '--step', '1', '--out', 'bad.png'], { PATH: dir, RBPART_CHROMIUM: '' });
  assert.equal(nochromium.status, 2);
  assert.match(nochromium.stderr, /chromium not found/);
  assert.equal(existsSync(join(dir, 'bad.png')), false);
});

// The Chain Drop's links lie along x (here 20 links of 0.1 m diameter, thick enough to be seen from
// afar) over a static slab much larger than the chain: framed on everything, the chain was a short
// line on the slab.
test('rbpart snapshot frames the dynamic bodies, seen from its camera options', { timeout: 90000 }, () => {
  const run = rbpart(['simulate', '--scene', 'chain_drop', '--set', 'links=20', '--set', 'radius=0.05', '--steps', '2',
    '--record', 'chain.rbrec', '-q']);
  assert.equal(run.status, 0, run.stderr);
  const extent = (name, camera) => {
    const shot = rbpart(['snapshot', 'chain.rbrec', '--step', '2', '--out', name, '--width', '400', '--height', '250',
      '--flat', ...camera]);
    assert.equal(shot.status, 0, shot.stderr);
    return paletteExtent(decodePng(readFileSync(join(dir, name))), PALETTE);
  };
  // The default three-quarter view, the slab drawn: the chain's box fills 90% of the view, and the
  // chain, its diagonal, spans most of the picture's width.
  const framed = extent('default.png', []);
  assert.ok(framed.width > 0.6, `the chain spans most of the width: ${JSON.stringify(framed)}`);
  // From +y, level: the chain runs across the picture, thin; zoom 0.5 doubles the distance, which
  // halves its projected length (0.9 of the width at zoom 1).
  const side = extent('side.png', ['--camera-azimuth', '90', '--camera-elevation', '0', '--zoom', '0.5']);
  assert.ok(side.width > 0.38 && side.width < 0.5, `half of 0.9 of the width: ${JSON.stringify(side)}`);
  assert.ok(side.height < 0.05, `seen level from the side, the chain is a thin line: ${JSON.stringify(side)}`);
  // From +x and above, along the chain: it runs up the picture, narrow.
  const along = extent('along.png', ['--camera-azimuth', '0', '--camera-elevation', '30']);
  assert.ok(along.width < 0.1 && along.height > 0.5, `the chain runs up the picture: ${JSON.stringify(along)}`);

  const bad = rbpart(['snapshot', 'chain.rbrec', '--step', '2', '--out', 'bad.png', '--zoom', '0']);
  assert.equal(bad.status, 2);
  assert.match(bad.stderr, /--zoom/);
});
