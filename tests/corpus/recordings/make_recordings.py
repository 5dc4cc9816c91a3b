#!/usr/bin/env python3
"""Writes the malformed recordings of this folder from valid.rbrec (docs/recording.md's layout).

valid.rbrec is `rbpart simulate --scene ../scenes/valid_chain.json --steps 3 --record valid.rbrec
--record-partitioners mindp,mix+fm`; run this script beside it after a change of the format.
"""
import gzip
import json
import struct
import zlib
from pathlib import Path

HERE = Path(__file__).resolve().parent
raw = gzip.decompress((HERE / "valid.rbrec").read_bytes())


def u32(data, at):
    return struct.unpack_from("<I", data, at)[0]


def put32(data, at, value):
    out = bytearray(data)
    struct.pack_into("<I", out, at, value)
    return bytes(out)


# Offsets of the parts: magic, version, header, bodies, frames, trailer.
VERSION, META_LEN, META = 8, 12, 16
meta_len = u32(raw, META_LEN)
meta = json.loads(raw[META:META + meta_len])
BODIES = META + meta_len
bodies = []  # (offset, shape code, offset of a convex hull's counts or None)
at = BODIES
for _ in range(meta["bodies"]):
    code = raw[at]
    shape = at + 48  # code, static, padding, pose (7 f32), mass, centre of mass (3 f32)
    hull = None
    if code == 0:
        end = shape + 4
    elif code == 1:
        end = shape + 12
    elif code in (2, 3):
        end = shape + 8
    else:
        hull = shape
        nv, nf, ni = struct.unpack_from("<III", raw, shape)
        end = shape + 12 + nv * 12 + (nf + 1 + ni) * 4
    bodies.append((at, code, hull))
    at = end
FRAMES = at
frames = []  # (offset of the length field, length)
while u32(raw, at) != 0:
    frames.append((at, u32(raw, at)))
    at += 4 + u32(raw, at)
TRAILER = at
nodes = sum(1 for b in bodies if raw[b[0] + 1] == 0)
stat_count = len(meta["stats"])
# In the first frame: step, time, stats, poses, then the edge count and the edges.
EDGES = frames[0][0] + 4 + 4 + 8 + 8 * stat_count + 28 * nodes
edges = u32(raw, EDGES)
CHANNEL = EDGES + 4 + 12 * edges + (4 - 12 * edges % 4) % 4  # the run's channel: 6 words, then part ids


def with_meta(change):
    """The recording with its header JSON changed, its length kept a multiple of 4."""
    m = json.loads(raw[META:META + meta_len])
    change(m)
    text = json.dumps(m).encode()
    text += b" " * (-len(text) % 4)
    return raw[:META_LEN] + struct.pack("<I", len(text)) + text + raw[BODIES:]


hull = next(b[2] for b in bodies if b[2] is not None)
nv, nf, ni = struct.unpack_from("<III", raw, hull)
first_index = hull + 12 + nv * 12 + (nf + 1) * 4
files = {
    # Not a gzip stream, or a broken one.
    "empty.rbrec": b"",
    "text.rbrec": b"RBPREC\r\nthis is not compressed\n",
    "gzip_truncated.rbrec": (HERE / "valid.rbrec").read_bytes()[:200],
    "gzip_corrupt.rbrec": None,  # below
    "zlib_not_gzip.rbrec": zlib.compress(raw),
    # The stream inflates, the contents are not a recording.
    "gzip_of_text.rbrec": gzip.compress(b"hello, world\n"),
    "bad_magic_line_ends.rbrec": gzip.compress(raw.replace(b"RBPREC\r\n", b"RBPREC\n\n", 1)),
    "magic_only_half.rbrec": gzip.compress(raw[:4]),
    "version_2.rbrec": gzip.compress(put32(raw, VERSION, 2)),
    "no_header_length.rbrec": gzip.compress(raw[:10]),
    "header_length_huge.rbrec": gzip.compress(put32(raw, META_LEN, 0xFFFFFFFF)),
    "header_not_json.rbrec": gzip.compress(raw[:META] + b"{" * meta_len + raw[BODIES:]),
    "header_no_bodies.rbrec": gzip.compress(with_meta(lambda m: m.pop("bodies"))),
    "header_bodies_negative.rbrec": gzip.compress(with_meta(lambda m: m.update(bodies=-1))),
    "header_bodies_huge_float.rbrec": gzip.compress(with_meta(lambda m: m.update(bodies=1e300))),
    "header_bodies_string.rbrec": gzip.compress(with_meta(lambda m: m.update(bodies="5"))),
    "header_no_channels.rbrec": gzip.compress(with_meta(lambda m: m.update(channels=[]))),
    "header_channels_number.rbrec": gzip.compress(with_meta(lambda m: m.update(channels=7))),
    "header_channel_without_name.rbrec": gzip.compress(with_meta(lambda m: m["channels"][0].pop("name"))),
    "header_stats_one_more.rbrec": gzip.compress(with_meta(lambda m: m["stats"].append("extra"))),
    "unknown_shape_code.rbrec": gzip.compress(raw[:BODIES] + b"\x09" + raw[BODIES + 1:]),
    "hull_vertex_count_huge.rbrec": gzip.compress(put32(raw, hull, 0xFFFFFFFF)),
    "hull_face_count_max.rbrec": gzip.compress(put32(raw, hull + 4, 0xFFFFFFFF)),
    "hull_index_out_of_range.rbrec": gzip.compress(put32(raw, first_index, nv)),
    "hull_offsets_decrease.rbrec": gzip.compress(put32(raw, hull + 12 + nv * 12 + 4, ni + 1)),
    "truncated_in_bodies.rbrec": gzip.compress(raw[:BODIES + 30]),
    "truncated_in_frame.rbrec": gzip.compress(raw[:frames[0][0] + 40]),
    "no_trailer.rbrec": gzip.compress(raw[:TRAILER]),
    "frame_length_odd.rbrec": gzip.compress(put32(raw, frames[0][0], frames[0][1] + 1)),
    "frame_length_short.rbrec": gzip.compress(put32(raw, frames[0][0], frames[0][1] - 4)),
    "frame_length_huge.rbrec": gzip.compress(put32(raw, frames[0][0], 0xFFFFFFFC)),
    "edge_count_huge.rbrec": gzip.compress(put32(raw, EDGES, 0x7FFFFFFF)),
    "edge_node_out_of_range.rbrec": gzip.compress(put32(raw, EDGES + 4 + 4 * edges, nodes)),
    "part_count_zero.rbrec": gzip.compress(put32(raw, CHANNEL, 0)),
    "part_id_out_of_range.rbrec": gzip.compress(put32(raw, CHANNEL + 24, 0xFFFFFFFF)),
    "trailer_count_wrong.rbrec": gzip.compress(put32(raw, TRAILER + 4, len(frames) + 1)),
    "data_after_trailer.rbrec": gzip.compress(raw + b"\0\0\0\0"),
    # Well formed, but nothing to show.
    "no_frames.rbrec": gzip.compress(raw[:FRAMES] + struct.pack("<II", 0, 0)),
}
valid_gz = bytearray((HERE / "valid.rbrec").read_bytes())
valid_gz[len(valid_gz) // 2] ^= 0xFF
files["gzip_corrupt.rbrec"] = bytes(valid_gz)
assert edges > 0 and nodes > 0 and len(frames) == 3
for name, data in files.items():
    (HERE / name).write_bytes(data)
print(f"{len(files)} recordings written")
