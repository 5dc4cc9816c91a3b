// rbpart viewer: opens a recording (embedded by `rbpart view --html`, served by `rbpart view`, or
// chosen/dropped by the user), then plays it. Options in the URL hash (docs/viewer.md):
//   src=URL  name=TEXT  step=K  channel=NAME  graph=1  statics=0  flat=1  speed=X  play=0|1  snapshot=1
//   azimuth=DEG  elevation=DEG  zoom=F (the first view of the dynamic bodies)
import { loadRecording } from './recording.js';
import { colourChannel, PALETTE } from './colouring.js';
import { SceneView } from './scene.js';

const $ = (id) => document.getElementById(id);
const options = new URLSearchParams(location.hash.slice(1));
const snapshot = options.get('snapshot') === '1';
const SPEEDS = [0.1, 0.25, 0.5, 1, 2, 4];

// Every failure ends here, so the page never stays blank.
function showError(message) {
  const box = $('error');
  box.textContent = message;
  box.hidden = false;
  document.body.classList.add('failed');
  document.title = 'rbpart viewer: error';
}
window.addEventListener('error', (e) => showError(`Viewer error: ${e.message}`));
window.addEventListener('unhandledrejection', (e) => showError(`Viewer error: ${e.reason?.message ?? e.reason}`));

let player = null;

class Player {
  constructor(recording, name) {
    this.rec = recording;
    this.frame = 0;
    this.channel = 0;
    this.colours = new Map(); // channel -> per-frame part colours
    this.playing = false;
    this.speed = 1;
    this.showGraph = false;
    this.clock = 0; // simulated seconds accumulated towards the next frame

    const canvas = document.createElement('canvas');
    canvas.id = 'view';
    $('view').replaceWith(canvas);
    this.view = new SceneView(canvas, recording, { flat: options.get('flat') === '1', camera: cameraOptions() });

    const meta = recording.meta;
    $('source').textContent = `${name} · scene ${meta.scene} · ${recording.bodyOf.length} bodies · ${recording.frames.length} steps`;
    const timeline = $('timeline');
    timeline.max = recording.frames.length - 1;
    const select = $('channel');
    select.replaceChildren(...recording.channels.map((c, i) => new Option(c, i)));
    select.disabled = recording.channels.length < 2;
  }

  coloursOf(channel) {
    if (!this.colours.has(channel)) this.colours.set(channel, colourChannel(this.rec, channel));
    return this.colours.get(channel);
  }

  show() {
    const frame = this.rec.frames[this.frame];
    this.view.show(this.frame, this.channel, this.coloursOf(this.channel)[this.frame], this.showGraph);
    $('timeline').value = this.frame;
    const counter = $('frame');
    counter.textContent = `step ${frame.step} / ${this.rec.frames[this.rec.frames.length - 1].step}`;
    counter.dataset.frame = this.frame;
    counter.dataset.step = frame.step;
    this.showStats(frame);
  }

  showStats(frame) {
    const c = frame.channels[this.channel];
    const s = frame.stats;
    const ms = (x) => (x === undefined ? '–' : `${x.toFixed(2)} ms`);
    const num = (x) => (x === undefined ? '–' : String(x));
    const rows = [
      ['time', `${frame.time.toFixed(3)} s`],
      ['partition', this.rec.channels[this.channel]],
      ['parts', c.parts],
      ['interface rows', c.interfaceRows],
      ['interface bodies', c.interfaceBodies],
      ['edge cut', c.edgeCut],
      ['partition', ms(c.partitionMs)],
      ['refine', ms(c.refineMs)],
      ['solve', ms(s.solve_ms)],
      ['solve critical path', ms(s.critical_path_ms)],
      ['step total', ms(s.total_ms)],
      ['contacts', num(s.contacts)],
      ['rows', num(s.rows)],
      ['islands', num(s.islands)],
      ['edges', frame.edgeU.length],
      ['solver iterations', num(s.solver_iterations)],
      ['factorisations', num(s.factorizations)],
      ['factorisations, largest island', num(s.island_factorizations)],
      ['unsettled islands', num(s.unsettled)],
      ['BLCP residual', s.blcp_residual === undefined ? '–' : s.blcp_residual.toExponential(2)],
      ['kinetic energy', s.kinetic_energy === undefined ? '–' : `${s.kinetic_energy.toPrecision(4)} J`],
    ];
    $('stats').replaceChildren(...rows.map(([k, v]) => {
      const tr = document.createElement('tr');
      tr.dataset.key = k;
      tr.append(Object.assign(document.createElement('th'), { textContent: k }),
        Object.assign(document.createElement('td'), { textContent: v }));
      return tr;
    }));
  }

  seek(f) {
    this.frame = Math.min(Math.max(f, 0), this.rec.frames.length - 1);
    this.clock = 0;
    this.show();
  }

  setPlaying(on) {
    this.playing = on;
    $('play').textContent = on ? 'Pause' : 'Play';
    this.lastTime = undefined;
    if (on) requestAnimationFrame((t) => this.tick(t));
  }

  // Real time × speed advances the simulated clock; every dt of it is one frame (looping).
  tick(now) {
    if (!this.playing || player !== this) return;
    if (this.lastTime !== undefined) {
      this.clock += ((now - this.lastTime) / 1000) * this.speed;
      const dt = this.rec.meta.dt > 0 ? this.rec.meta.dt : 1 / 60;
      const advance = Math.floor(this.clock / dt);
      if (advance > 0) {
        this.clock -= advance * dt;
        this.frame = (this.frame + advance) % this.rec.frames.length;
        this.show();
      }
    }
    this.lastTime = now;
    requestAnimationFrame((t) => this.tick(t));
  }

  resize() {
    const canvas = this.view.renderer.domElement;
    this.view.resize(canvas.clientWidth, canvas.clientHeight);
  }
}

async function open(bytes, name) {
  $('error').hidden = true;
  document.body.classList.remove('failed');
  $('hint').hidden = true;
  let recording;
  try {
    recording = await loadRecording(bytes);
  } catch (e) {
    showError(`Cannot open ${name}: ${e.message}`);
    return;
  }
  if (player) {
    player.setPlaying(false);
    player.view.renderer.dispose(); // its canvas is replaced: release the WebGL context
  }
  try {
    player = new Player(recording, name);
    applyOptions(player);
  } catch (e) {
    showError(`Cannot show ${name}: ${e.message}`);
    return;
  }
  document.body.classList.add('loaded');
  player.show();
  player.resize(); // the first resize frames the camera on the bodies as shown
  player.setPlaying(!snapshot && options.get('play') !== '0');
  document.title = `rbpart viewer: ${recording.meta.scene}`;
  if (snapshot) document.title = 'rbpart viewer: ready';
}

// The URL's camera: azimuth and elevation in degrees, zoom a positive factor (2: twice as close).
function cameraOptions() {
  const camera = {};
  for (const [key, valid] of [['azimuth', Number.isFinite], ['elevation', (x) => Math.abs(x) <= 90],
    ['zoom', (x) => x > 0 && Number.isFinite(x)]]) {
    if (!options.has(key)) continue;
    const value = Number(options.get(key));
    if (options.get(key).trim() === '' || !valid(value)) throw new Error(`bad ${key}=${options.get(key)}`);
    camera[key] = value;
  }
  return camera;
}

// The URL's step, channel, graph and speed options, for links and `rbpart snapshot`.
function applyOptions(p) {
  if (options.has('channel')) {
    const c = p.rec.channels.indexOf(options.get('channel'));
    if (c < 0) throw new Error(`no partition channel '${options.get('channel')}' (the recording has: ${p.rec.channels.join(', ')})`);
    p.channel = c;
    $('channel').value = c;
  }
  if (options.has('step')) {
    const step = Number(options.get('step'));
    const f = p.rec.frames.findIndex((fr) => fr.step === step);
    if (f < 0) throw new Error(`no step ${options.get('step')} in the recording`);
    p.frame = f;
  }
  p.showGraph = options.get('graph') === '1';
  $('graph').checked = p.showGraph;
  $('statics').checked = options.get('statics') !== '0';
  p.view.setStaticVisible($('statics').checked);
  if (options.has('speed')) p.speed = Number(options.get('speed')) || 1;
  $('speed').value = p.speed;
}

function base64Bytes(text) {
  const binary = atob(text.replace(/\s+/g, ''));
  const bytes = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; ++i) bytes[i] = binary.charCodeAt(i);
  return bytes.buffer;
}

function setUp() {
  if (snapshot) document.body.classList.add('snapshot');
  $('speed').replaceChildren(...SPEEDS.map((s) => new Option(`${s}×`, s)));
  $('speed').value = 1;
  $('legend').replaceChildren(...PALETTE.map((c) => {
    const swatch = document.createElement('span');
    swatch.style.background = `#${c.toString(16).padStart(6, '0')}`;
    return swatch;
  }));

  $('file').addEventListener('change', async (e) => {
    const file = e.target.files[0];
    if (file) await open(await file.arrayBuffer(), file.name);
  });
  document.addEventListener('dragover', (e) => e.preventDefault());
  document.addEventListener('drop', async (e) => {
    e.preventDefault();
    const file = e.dataTransfer.files[0];
    if (file) await open(await file.arrayBuffer(), file.name);
  });
  $('play').addEventListener('click', () => player && player.setPlaying(!player.playing));
  $('speed').addEventListener('change', (e) => player && (player.speed = Number(e.target.value)));
  $('timeline').addEventListener('input', (e) => player && player.seek(Number(e.target.value)));
  $('channel').addEventListener('change', (e) => {
    if (!player) return;
    player.channel = Number(e.target.value);
    player.show();
  });
  $('graph').addEventListener('change', (e) => {
    if (!player) return;
    player.showGraph = e.target.checked;
    player.show();
  });
  $('statics').addEventListener('change', (e) => {
    if (!player) return;
    player.view.setStaticVisible(e.target.checked);
    player.show();
  });
  document.addEventListener('keydown', (e) => {
    if (!player || e.target.tagName === 'INPUT' || e.target.tagName === 'SELECT') return;
    if (e.key === ' ') player.setPlaying(!player.playing);
    else if (e.key === 'ArrowRight') player.seek(player.frame + 1);
    else if (e.key === 'ArrowLeft') player.seek(player.frame - 1);
    else return;
    e.preventDefault();
  });
  window.addEventListener('resize', () => player && player.resize());

  // Where the recording comes from: embedded (self-contained HTML), the URL, or the user.
  const embedded = $('rbpart-recording');
  const src = options.get('src');
  if (embedded) {
    open(base64Bytes(embedded.textContent), embedded.dataset.name || 'recording').catch((e) => showError(e.message));
  } else if (src) {
    fetch(src)
      .then((r) => {
        if (!r.ok) throw new Error(`HTTP ${r.status}`);
        return r.arrayBuffer();
      })
      .then((bytes) => open(bytes, options.get('name') || src))
      .catch((e) => showError(`Cannot open ${src}: ${e.message}`));
  } else {
    $('hint').hidden = false;
  }
}

setUp();
