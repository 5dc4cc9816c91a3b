// Reads an rbpart recording (docs/recording.md): inflates the gzip stream, checks the structure,
// and returns typed-array views into the inflated bytes (no copies of the per-frame arrays).

export const MAGIC = [0x52, 0x42, 0x50, 0x52, 0x45, 0x43, 0x0d, 0x0a]; // "RBPREC\r\n"
export const VERSION = 1;
export const SHAPES = ['sphere', 'box', 'capsule', 'cylinder', 'convex'];

export class RecordingError extends Error {}

// Inflates a gzip-compressed recording; rejects with a RecordingError that says what is wrong.
export async function inflate(bytes) {
  const head = new Uint8Array(bytes, 0, Math.min(2, bytes.byteLength));
  if (head.length < 2 || head[0] !== 0x1f || head[1] !== 0x8b)
    throw new RecordingError('not an rbpart recording (not gzip-compressed data)');
  try {
    const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream('gzip'));
    return await new Response(stream).arrayBuffer();
  } catch (e) {
    throw new RecordingError(`the gzip stream is corrupt or truncated (${e.message})`);
  }
}

class Reader {
  constructor(buffer) {
    this.buffer = buffer;
    this.view = new DataView(buffer);
    this.pos = 0;
  }
  fail(what) {
    throw new RecordingError(`malformed recording: ${what}`);
  }
  need(n, what) {
    if (n > this.buffer.byteLength - this.pos) this.fail(`truncated in ${what}`);
  }
  u8(what) { this.need(1, what); return this.view.getUint8(this.pos++); }
  u16(what) { this.need(2, what); const v = this.view.getUint16(this.pos, true); this.pos += 2; return v; }
  u32(what) { this.need(4, what); const v = this.view.getUint32(this.pos, true); this.pos += 4; return v; }
  i32(what) { this.need(4, what); const v = this.view.getInt32(this.pos, true); this.pos += 4; return v; }
  f32(what) { this.need(4, what); const v = this.view.getFloat32(this.pos, true); this.pos += 4; return v; }
  f64(what) { this.need(8, what); const v = this.view.getFloat64(this.pos, true); this.pos += 8; return v; }
  // A typed-array view of `count` items at the current position (aligned by the format).
  array(Type, count, what) {
    this.need(count * Type.BYTES_PER_ELEMENT, what);
    if (this.pos % Type.BYTES_PER_ELEMENT) this.fail(`misaligned ${what}`);
    const a = new Type(this.buffer, this.pos, count);
    this.pos += count * Type.BYTES_PER_ELEMENT;
    return a;
  }
  pad4(what) { while (this.pos % 4) this.u8(what); }
}

// Typed arrays use the host's byte order; the format is little-endian.
const littleEndian = new Uint8Array(new Uint16Array([1]).buffer)[0] === 1;

function readBody(r) {
  const code = r.u8('shapes');
  const body = { shape: SHAPES[code], isStatic: r.u8('shapes') !== 0 };
  if (body.shape === undefined) r.fail(`unknown shape code ${code}`);
  r.u16('shapes');
  body.pose = r.array(Float32Array, 7, 'shapes');
  body.mass = r.f32('shapes');
  body.com = r.array(Float32Array, 3, 'shapes');
  switch (body.shape) {
    case 'sphere': body.radius = r.f32('shapes'); break;
    case 'box': body.halfExtents = r.array(Float32Array, 3, 'shapes'); break;
    case 'capsule':
    case 'cylinder':
      body.radius = r.f32('shapes');
      body.halfLength = r.f32('shapes');
      break;
    case 'convex': {
      const nv = r.u32('hull'), nf = r.u32('hull'), ni = r.u32('hull');
      body.vertices = r.array(Float32Array, 3 * nv, 'hull');
      body.faceOffsets = r.array(Uint32Array, nf + 1, 'hull');
      body.faceIndices = r.array(Uint32Array, ni, 'hull');
      if (body.faceOffsets[0] !== 0 || body.faceOffsets[nf] !== ni) r.fail('hull face offsets');
      for (let f = 0; f < nf; ++f)
        if (body.faceOffsets[f] > body.faceOffsets[f + 1]) r.fail('hull face offsets decrease');
      for (const i of body.faceIndices) if (i >= nv) r.fail('hull vertex index out of range');
      break;
    }
  }
  return body;
}

function readChannel(r, nodes, edges) {
  const c = {
    parts: r.u32('channel'),
    edgeCut: r.u32('channel'),
    interfaceRows: r.u32('channel'),
    interfaceBodies: r.u32('channel'),
    partitionMs: r.f32('channel'),
    refineMs: r.f32('channel'),
  };
  c.partOf = r.array(Uint32Array, nodes, 'part ids');
  for (const p of c.partOf) if (p >= c.parts) r.fail('part id out of range');
  c.interface = new Uint8Array(r.buffer, r.pos, Math.ceil(edges / 8));
  r.need(c.interface.length, 'interface bits');
  r.pos += c.interface.length;
  r.pad4('interface bits');
  return c;
}

export function isInterface(channel, e) {
  return (channel.interface[e >> 3] >> (e & 7)) & 1;
}

// Parses inflated bytes: { meta, bodies, bodyOf (node -> body), channels (names), frames }.
export function parseRecording(buffer) {
  if (!littleEndian) throw new RecordingError('this viewer needs a little-endian machine');
  const r = new Reader(buffer);
  const magic = new Uint8Array(buffer, 0, Math.min(8, buffer.byteLength));
  if (magic.length < 8 || MAGIC.some((b, i) => magic[i] !== b))
    throw new RecordingError('not an rbpart recording (bad magic)');
  r.pos = 8;
  const version = r.u32('header');
  if (version !== VERSION)
    throw new RecordingError(`recording format version ${version} (this viewer reads ${VERSION})`);
  const metaBytes = r.u32('header');
  r.need(metaBytes, 'header');
  let meta;
  try {
    meta = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, r.pos, metaBytes)));
  } catch (e) {
    r.fail('the header is not JSON');
  }
  r.pos += metaBytes;
  if (!Array.isArray(meta.channels) || meta.channels.length === 0) r.fail('no partition channel');
  if (!Array.isArray(meta.stats)) r.fail('no statistics list');
  if (!Number.isInteger(meta.bodies) || meta.bodies < 0) r.fail('no body count');

  const bodies = [];
  const bodyOf = [];
  for (let i = 0; i < meta.bodies; ++i) {
    const body = readBody(r);
    if (!body.isStatic) bodyOf.push(i);
    bodies.push(body);
  }
  const nodes = bodyOf.length;
  const frames = [];
  for (;;) {
    const length = r.u32('frame length');
    if (length === 0) break;
    if (length % 4 || length > buffer.byteLength - r.pos)
      r.fail(`frame ${frames.length + 1} is truncated`);
    const end = r.pos + length;
    const f = { step: r.i32('frame') };
    f.time = r.f64('frame');
    f.stats = {};
    for (const name of meta.stats) f.stats[name] = r.f64('frame stats');
    f.poses = r.array(Float32Array, 7 * nodes, 'poses');
    const edges = r.u32('edges');
    f.edgeU = r.array(Uint32Array, edges, 'edges');
    f.edgeV = r.array(Uint32Array, edges, 'edges');
    f.weight = r.array(Uint16Array, edges, 'edges');
    f.rows = r.array(Uint16Array, edges, 'edges');
    r.pad4('edges');
    for (let e = 0; e < edges; ++e)
      if (f.edgeU[e] >= f.edgeV[e] || f.edgeV[e] >= nodes) r.fail('edge node out of range');
    f.channels = meta.channels.map(() => readChannel(r, nodes, edges));
    if (r.pos !== end) r.fail(`frame ${frames.length + 1} has the wrong length`);
    frames.push(f);
  }
  if (r.u32('trailer') !== frames.length) r.fail("the trailer's frame count does not match");
  if (r.pos !== buffer.byteLength) r.fail('data after the trailer');
  if (frames.length === 0) throw new RecordingError('the recording holds no step');
  return { meta, bodies, bodyOf, channels: meta.channels.map((c) => String(c.name)), frames };
}

export async function loadRecording(bytes) {
  return parseRecording(await inflate(bytes));
}
