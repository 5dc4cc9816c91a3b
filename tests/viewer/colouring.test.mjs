// The viewer's part colouring (docs/viewer.md, "Colouring"), checked on synthetic frames: parts
// joined by an edge differ whenever the palette allows, and a part that persists keeps its colour
// while the partition around it is renumbered and changes.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { colourChannel, PALETTE } from '../../viewer/src/colouring.js';

// Deterministic pseudo-random numbers (mulberry32).
function random(seed) {
  return () => {
    seed = (seed + 0x6d2b79f5) | 0;
    let t = Math.imul(seed ^ (seed >>> 15), 1 | seed);
    t = (t + Math.imul(t ^ (t >>> 7), 61 | t)) ^ t;
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
}

// A frame of a one-channel recording: edges (u < v) and part ids.
function frame(edges, partOf) {
  const parts = Math.max(-1, ...partOf) + 1;
  return {
    edgeU: Uint32Array.from(edges.map((e) => e[0])),
    edgeV: Uint32Array.from(edges.map((e) => e[1])),
    channels: [{ parts, partOf: Uint32Array.from(partOf) }],
  };
}

test('parts joined by an edge get different colours', () => {
  const rand = random(7);
  for (let trial = 0; trial < 50; ++trial) {
    const n = 20 + Math.floor(rand() * 200);
    const edges = [];
    for (let k = 0; k < 2 * n; ++k) {
      const u = Math.floor(rand() * n), v = Math.floor(rand() * n);
      if (u !== v) edges.push([Math.min(u, v), Math.max(u, v)]);
    }
    const frames = [0, 1, 2].map(() => frame(edges, Array.from({ length: n }, () => Math.floor(rand() * 12))));
    const rec = { bodyOf: Array.from({ length: n }, (_, i) => i), frames };
    const colours = colourChannel(rec, 0);
    frames.forEach((f, i) => {
      const c = colours[i];
      const partOf = f.channels[0].partOf;
      // With 12 parts, a part has at most 11 neighbours: the palette always suffices.
      for (const [u, v] of edges)
        if (partOf[u] !== partOf[v]) assert.notEqual(c[partOf[u]], c[partOf[v]], `trial ${trial} frame ${i}`);
      for (const k of c) assert.ok(k >= 0 && k < PALETTE.length);
    });
  }
});

test('a persisting part keeps its colour when ids are renumbered', () => {
  // A path 0-1-...-11: parts {0..3}, {4..7}, {8..11}; then the same parts with ids reversed and
  // the last one split in two.
  const edges = Array.from({ length: 11 }, (_, i) => [i, i + 1]);
  const first = [0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2];
  const second = [3, 3, 3, 3, 2, 2, 2, 2, 1, 1, 0, 0];
  const rec = { bodyOf: first.map((_, i) => i), frames: [frame(edges, first), frame(edges, second)] };
  const [c0, c1] = colourChannel(rec, 0);
  assert.equal(c1[3], c0[0]);
  assert.equal(c1[2], c0[1]);
  // The split part: one half keeps the colour, the other (its neighbour) gets another.
  assert.ok(c1[1] === c0[2] || c1[0] === c0[2]);
  assert.notEqual(c1[1], c1[0]);
  assert.notEqual(c1[1], c1[2]);
});

test('more neighbours than colours still yields palette colours', () => {
  // 14 single-node parts, all joined to each other: a clique needs 14 colours, the palette has 12.
  const n = 14;
  const edges = [];
  for (let u = 0; u < n; ++u) for (let v = u + 1; v < n; ++v) edges.push([u, v]);
  const rec = { bodyOf: Array.from({ length: n }, (_, i) => i), frames: [frame(edges, [...Array(n).keys()])] };
  const [c] = colourChannel(rec, 0);
  assert.equal(new Set(c).size, PALETTE.length);
});
