// Part colours (docs/viewer.md, "Colouring"): in every frame, parts joined by a constraint-graph
// edge get different colours whenever the palette allows (a greedy colouring of the part adjacency
// graph), and a part keeps the colour most of its bodies had in the previous frame, so colours
// follow the bodies while the partition is recomputed every step.

// Twelve colours far apart in hue and lightness, none grey (grey is for static bodies).
export const PALETTE = [
  0xe6194b, 0x3cb44b, 0x4363d8, 0xffe119, 0xf58231, 0x911eb4,
  0x42d4f4, 0xf032e6, 0xbfef45, 0x469990, 0x9a6324, 0x800000,
];
const K = PALETTE.length;

// One Uint8Array of palette indices per frame: the colour of each part of `channel`.
export function colourChannel(recording, channel) {
  const nodes = recording.bodyOf.length;
  let previous = null; // node -> colour in the previous frame
  return recording.frames.map((frame) => {
    const c = frame.channels[channel];
    const P = c.parts;
    const partOf = c.partOf;
    // Part adjacency from the interface edges, as neighbour lists.
    const neighbours = Array.from({ length: P }, () => []);
    for (let e = 0; e < frame.edgeU.length; ++e) {
      const a = partOf[frame.edgeU[e]], b = partOf[frame.edgeV[e]];
      if (a !== b) {
        neighbours[a].push(b);
        neighbours[b].push(a);
      }
    }
    // Votes: how many of a part's bodies had each colour in the previous frame.
    const size = new Uint32Array(P);
    const votes = new Uint32Array(P * K);
    for (let v = 0; v < nodes; ++v) {
      size[partOf[v]]++;
      if (previous) votes[partOf[v] * K + previous[v]]++;
    }
    // Large parts choose first: they are what the eye follows.
    const order = Array.from({ length: P }, (_, p) => p).sort((a, b) => size[b] - size[a] || a - b);
    const colour = new Int16Array(P).fill(-1);
    const uses = new Uint32Array(K); // parts of this frame per colour, to spread new colours
    const taken = new Uint32Array(K);
    for (const p of order) {
      taken.fill(0);
      for (const q of neighbours[p]) if (colour[q] >= 0) taken[colour[q]]++;
      // Free colour with the most votes; among unvoted free colours the least used in this frame.
      let best = -1;
      for (let k = 0; k < K; ++k) {
        if (taken[k]) continue;
        if (best < 0) { best = k; continue; }
        const dv = votes[p * K + k] - votes[p * K + best];
        if (dv > 0 || (dv === 0 && uses[k] < uses[best])) best = k;
      }
      // More coloured neighbours than colours: the colour fewest neighbours have.
      if (best < 0) {
        best = 0;
        for (let k = 1; k < K; ++k) if (taken[k] < taken[best]) best = k;
      }
      colour[p] = best;
      uses[best]++;
    }
    previous = new Uint8Array(nodes);
    for (let v = 0; v < nodes; ++v) previous[v] = colour[partOf[v]];
    return Uint8Array.from(colour);
  });
}
