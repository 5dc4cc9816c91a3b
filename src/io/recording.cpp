#include "io/recording.hpp"

#include "io/atomic_file.hpp"
#include "core/error.hpp"
#include "geometry/hull.hpp"
#include "graph/constraint_graph.hpp"
#include "partition/partition.hpp"
#include "scene/bodies.hpp"
#include "step/world_internals.hpp"

#include <zlib.h>

#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace rbpart {

namespace {

using Json = nlohmann::ordered_json;

// The frame statistics, named as the stats CSV columns (io/stats_csv.hpp), each with its source.
using StatField = std::pair<const char*, double (*)(const StepStats&)>;
const StatField kStatFields[] = {
    {"bodies", [](const StepStats& s) -> double { return s.bodies; }},
    {"contacts", [](const StepStats& s) -> double { return s.contacts; }},
    {"rows", [](const StepStats& s) -> double { return s.rows; }},
    {"islands", [](const StepStats& s) -> double { return s.islands; }},
    {"parts", [](const StepStats& s) -> double { return s.partition.parts; }},
    {"interface_rows", [](const StepStats& s) -> double { return s.partition.interface_rows; }},
    {"interface_bodies", [](const StepStats& s) -> double { return s.partition.interface_bodies; }},
    {"edge_cut", [](const StepStats& s) -> double { return s.partition.edge_cut; }},
    {"collide_ms", [](const StepStats& s) { return s.profile.collide_ms; }},
    {"assemble_ms", [](const StepStats& s) { return s.profile.assemble_ms; }},
    {"graph_ms", [](const StepStats& s) { return s.profile.graph_ms; }},
    {"partition_ms", [](const StepStats& s) { return s.profile.partition_ms; }},
    {"refine_ms", [](const StepStats& s) { return s.profile.refine_ms; }},
    {"solve_ms", [](const StepStats& s) { return s.profile.solve_ms; }},
    {"integrate_ms", [](const StepStats& s) { return s.profile.integrate_ms; }},
    {"project_ms", [](const StepStats& s) { return s.profile.project_ms; }},
    {"total_ms", [](const StepStats& s) { return s.profile.total_ms; }},
    {"solver_iterations", [](const StepStats& s) -> double { return s.solve.iterations; }},
    {"factorizations", [](const StepStats& s) -> double { return s.solve.factorizations; }},
    {"blcp_residual", [](const StepStats& s) { return s.solve.residual; }},
    {"max_penetration", [](const StepStats& s) { return s.max_penetration; }},
    {"kinetic_energy", [](const StepStats& s) { return s.kinetic_energy; }},
    {"critical_path_ms", [](const StepStats& s) { return s.solve.critical_path_ms; }},
    {"unsettled", [](const StepStats& s) -> double { return s.solve.unsettled; }},
    {"island_factorizations", [](const StepStats& s) -> double { return s.solve.island_factorizations; }},
};

enum ShapeCode : std::uint8_t { kSphere = 0, kBox = 1, kCapsule = 2, kCylinder = 3, kConvex = 4 };

// Little-endian encoding whatever the host's byte order (docs/recording.md).
class ByteWriter {
 public:
  explicit ByteWriter(std::string& out) : out_(out) {}
  void u8(std::uint8_t v) { out_.push_back(static_cast<char>(v)); }
  void u16(std::uint16_t v) { bytes(v, 2); }
  void u32(std::uint32_t v) { bytes(v, 4); }
  void i32(std::int32_t v) { bytes(static_cast<std::uint32_t>(v), 4); }
  void f32(float v) {
    std::uint32_t bits;
    std::memcpy(&bits, &v, 4);
    bytes(bits, 4);
  }
  void f64(double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, 8);
    bytes(bits, 8);
  }
  // Zeros up to the next multiple of 4 bytes, so that every array starts 4-byte aligned and the
  // viewer can view it as a typed array without copying.
  void pad4() {
    while (out_.size() % 4) out_.push_back('\0');
  }

 private:
  void bytes(std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i) out_.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
  }
  std::string& out_;
};

std::uint32_t count32(std::size_t n, const char* what) {
  if (n > std::numeric_limits<std::uint32_t>::max())
    throw std::length_error(std::string("recording: too many ") + what);
  return static_cast<std::uint32_t>(n);
}

std::uint16_t count16(int n, const char* what) {
  if (n < 0 || n > std::numeric_limits<std::uint16_t>::max())
    throw std::length_error(std::string("recording: ") + what + " out of range");
  return static_cast<std::uint16_t>(n);
}

void write_pose(ByteWriter& w, const Vec3& p, const Quat& q) {
  for (int k = 0; k < 3; ++k) w.f32(static_cast<float>(p[k]));
  w.f32(static_cast<float>(q.w()));
  w.f32(static_cast<float>(q.x()));
  w.f32(static_cast<float>(q.y()));
  w.f32(static_cast<float>(q.z()));
}

void write_body(ByteWriter& w, const BodyDef& body, const Bodies& bodies, int i) {
  const Shape& s = body.shape;
  const ShapeCode code = s.type == ShapeType::Sphere    ? kSphere
                         : s.type == ShapeType::Box     ? kBox
                         : s.type == ShapeType::Capsule ? kCapsule
                         : s.type == ShapeType::Cylinder ? kCylinder
                                                         : kConvex;
  w.u8(code);
  w.u8(body.is_static ? 1 : 0);
  w.u16(0);
  write_pose(w, bodies.frame_position(i), bodies.q[i]);
  w.f32(static_cast<float>(bodies.mass[i]));
  for (int k = 0; k < 3; ++k) w.f32(static_cast<float>(bodies.com_local[i][k]));
  switch (code) {
    case kSphere: w.f32(static_cast<float>(s.radius)); break;
    case kBox:
      for (int k = 0; k < 3; ++k) w.f32(static_cast<float>(s.half_extents[k]));
      break;
    case kCapsule:
    case kCylinder:
      w.f32(static_cast<float>(s.radius));
      w.f32(static_cast<float>(s.half_length));
      break;
    case kConvex: {
      // The hull the collider and mass properties use (geometry/hull.hpp), so the viewer draws the same
      // polyhedron that collides.
      const HullFaces hull = convex_hull_faces(s.vertices);
      w.u32(count32(s.vertices.size(), "hull vertices"));
      w.u32(count32(hull.size(), "hull faces"));
      w.u32(count32(hull.indices.size(), "hull indices"));
      for (const Vec3& v : s.vertices)
        for (int k = 0; k < 3; ++k) w.f32(static_cast<float>(v[k]));
      for (int o : hull.offsets) w.u32(static_cast<std::uint32_t>(o));
      if (hull.offsets.empty()) w.u32(0);  // no face: the offsets are the single sentinel 0
      for (int i : hull.indices) w.u32(static_cast<std::uint32_t>(i));
      break;
    }
  }
}

// gzip (RFC 1952) stream into an AtomicFile, one deflate call per appended buffer.
class GzipSink {
 public:
  explicit GzipSink(const std::string& path) : file_(path) {
    // windowBits 15 + 16: a gzip wrapper, which DecompressionStream('gzip') reads.
    if (deflateInit2(&z_, Z_DEFAULT_COMPRESSION, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
      throw std::runtime_error("recording: deflateInit2 failed");
  }
  ~GzipSink() { deflateEnd(&z_); }
  GzipSink(const GzipSink&) = delete;
  GzipSink& operator=(const GzipSink&) = delete;

  void write(const std::string& data) { deflate_all(data, Z_NO_FLUSH); }
  void finish() {
    deflate_all({}, Z_FINISH);
    file_.commit();
  }

 private:
  void deflate_all(const std::string& data, int flush) {
    z_.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
    z_.avail_in = static_cast<uInt>(data.size());
    int ret;
    do {
      z_.next_out = out_;
      z_.avail_out = sizeof(out_);
      ret = deflate(&z_, flush);
      if (ret == Z_STREAM_ERROR) throw std::runtime_error("recording: deflate failed");
      file_.write(std::string_view(reinterpret_cast<const char*>(out_), sizeof(out_) - z_.avail_out));
    } while (z_.avail_out == 0 || (flush == Z_FINISH && ret != Z_STREAM_END));
  }

  AtomicFile file_;
  z_stream z_{};
  unsigned char out_[1 << 16];
};

}  // namespace

const std::vector<std::string> kRecordedStats = [] {
  std::vector<std::string> names;
  for (const StatField& f : kStatFields) names.emplace_back(f.first);
  return names;
}();

std::string channel_name(const PartitionParams& params) {
  std::string name = partitioner_name(params.partitioner);
  if (params.refiner != RefinerKind::None) name += std::string("+") + refiner_name(params.refiner);
  return name;
}

std::vector<PartitionParams> parse_channel_list(const std::string& list, const PartitionParams& base) {
  std::vector<PartitionParams> channels;
  std::stringstream items(list);
  std::string item;
  while (std::getline(items, item, ',')) {
    if (item.empty()) throw InputError("--record-partitioners: empty item in '" + list + "'");
    PartitionParams p = base;
    const auto plus = item.find('+');
    p.partitioner = parse_partitioner(item.substr(0, plus));
    p.refiner = plus == std::string::npos ? RefinerKind::None : parse_refiner(item.substr(plus + 1));
    if (p.partitioner == PartitionerKind::None)
      throw InputError("--record-partitioners: '" + item + "' names no partitioner");
    channels.push_back(p);
  }
  if (!list.empty() && list.back() == ',') throw InputError("--record-partitioners: empty item in '" + list + "'");
  return channels;
}

struct RecordingWriter::Impl {
  GzipSink sink;
  std::vector<PartitionParams> extra;
  int nodes = 0;
  std::uint32_t frames = 0;
  std::string frame;         // reused per step
  // Reused per step: the edges (u < v) with their weights and rows, a channel's interface bits and
  // interface bodies.
  std::vector<std::uint32_t> eu, ev;
  std::vector<std::uint16_t> ew, er;
  std::vector<std::uint8_t> bits;
  std::vector<char> is_interface_body;

  Impl(const std::string& path, std::vector<PartitionParams> extra_channels)
      : sink(path), extra(std::move(extra_channels)) {}

  // One channel: counts, part ids, interface bits (docs/design.md#graph: an edge is an interface edge when
  // its bodies lie in different parts; its constraints are the edge cut, its rows the interface rows).
  void write_channel(ByteWriter& w, const ConstraintGraph& g, const Partition& p, double partition_ms,
                     double refine_ms) {
    if (static_cast<int>(p.part_of.size()) != g.node_count())
      throw std::logic_error("recording: partition does not match the graph");
    std::uint32_t cut = 0, interface_rows = 0, interface_bodies = 0;
    is_interface_body.assign(g.node_count(), 0);
    bits.assign((eu.size() + 7) / 8, 0);
    for (std::size_t e = 0; e < eu.size(); ++e) {
      if (p.part_of[eu[e]] == p.part_of[ev[e]]) continue;
      bits[e >> 3] |= static_cast<std::uint8_t>(1u << (e & 7));
      cut += ew[e];
      interface_rows += er[e];
      is_interface_body[eu[e]] = is_interface_body[ev[e]] = 1;
    }
    for (char c : is_interface_body) interface_bodies += c;
    w.u32(static_cast<std::uint32_t>(p.part_count));
    w.u32(cut);
    w.u32(interface_rows);
    w.u32(interface_bodies);
    w.f32(static_cast<float>(partition_ms));
    w.f32(static_cast<float>(refine_ms));
    for (int part : p.part_of) w.u32(static_cast<std::uint32_t>(part));
    for (std::uint8_t b : bits) w.u8(b);
    w.pad4();
  }
};

RecordingWriter::RecordingWriter(const std::string& path, const World& world, const ParamList& params,
                                 const std::string& run_channel, std::vector<PartitionParams> extra)
    : impl_(std::make_unique<Impl>(path, std::move(extra))) {
  const SceneDef& scene = world.scene();
  Json meta = Json::object();
  meta["format"] = "rbpart recording";
  meta["scene"] = scene.name;
  meta["dt"] = scene.dt;
  meta["gravity"] = {scene.gravity.x(), scene.gravity.y(), scene.gravity.z()};
  meta["bodies"] = scene.bodies.size();
  for (const BodyDef& b : scene.bodies) impl_->nodes += !b.is_static;
  meta["nodes"] = impl_->nodes;
  meta["params"] = params_json(params);
  Json channels = Json::array();
  channels.push_back({{"name", run_channel}, {"source", "run"}});
  for (const PartitionParams& c : impl_->extra)
    channels.push_back({{"name", channel_name(c)},
                        {"source", "recorder"},
                        {"partitioner", partitioner_name(c.partitioner)},
                        {"refiner", refiner_name(c.refiner)},
                        {"nmax", c.nmax},
                        {"tau_mr", c.tau_mr},
                        {"tau_mix", c.tau_mix}});
  meta["channels"] = std::move(channels);
  meta["stats"] = kRecordedStats;
  std::string meta_text = meta.dump();
  while (meta_text.size() % 4) meta_text.push_back(' ');

  std::string header(kRecordingMagic.begin(), kRecordingMagic.end());
  ByteWriter w(header);
  w.u32(kRecordingVersion);
  w.u32(count32(meta_text.size(), "header bytes"));
  header += meta_text;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i)
    write_body(w, scene.bodies[i], world_bodies(world), static_cast<int>(i));
  impl_->sink.write(header);
}

RecordingWriter::~RecordingWriter() = default;

void RecordingWriter::write_step(const World& world, const StepStats& stats,
                                 const std::vector<ChannelPartition>& extra) {
  Impl& m = *impl_;
  const Bodies& bodies = world_bodies(world);
  const ConstraintGraph& g = world_graph(world);
  if (g.node_count() != m.nodes) throw std::logic_error("recording: node count changed");
  if (extra.size() != m.extra.size()) throw std::logic_error("recording: one partition per extra channel expected");

  // Edges once per pair (u < v); CSR neighbours are sorted, so the list is sorted by (u, v).
  m.eu.clear();
  m.ev.clear();
  m.ew.clear();
  m.er.clear();
  for (int u = 0; u < g.node_count(); ++u)
    for (int k = g.offset[u]; k < g.offset[u + 1]; ++k) {
      const int v = g.adjacency[k];
      if (v <= u) continue;
      m.eu.push_back(static_cast<std::uint32_t>(u));
      m.ev.push_back(static_cast<std::uint32_t>(v));
      m.ew.push_back(count16(g.weight[k], "edge weight"));
      m.er.push_back(count16(g.rows[k], "edge rows"));
    }

  m.frame.clear();
  ByteWriter w(m.frame);
  w.u32(0);  // frame length, filled in below
  w.i32(stats.step);
  w.f64(world.time());
  for (const StatField& f : kStatFields) w.f64(f.second(stats));
  for (int node = 0; node < g.node_count(); ++node) {
    const int i = g.body_of[node];
    write_pose(w, bodies.frame_position(i), bodies.q[i]);
  }
  w.u32(count32(m.eu.size(), "edges"));
  for (std::uint32_t u : m.eu) w.u32(u);
  for (std::uint32_t v : m.ev) w.u32(v);
  for (std::uint16_t x : m.ew) w.u16(x);
  for (std::uint16_t x : m.er) w.u16(x);
  w.pad4();
  m.write_channel(w, g, world_partition(world), stats.profile.partition_ms, stats.profile.refine_ms);
  for (const ChannelPartition& c : extra)
    m.write_channel(w, g, c.partition, c.quality.partition_ms, c.quality.refine_ms);
  const std::uint32_t length = count32(m.frame.size() - 4, "frame bytes");
  for (int i = 0; i < 4; ++i) m.frame[i] = static_cast<char>((length >> (8 * i)) & 0xff);
  m.sink.write(m.frame);
  ++m.frames;
}

void RecordingWriter::finish() {
  // Trailer: a zero frame length, then the frame count, so a reader can tell a complete recording
  // from a truncated one.
  std::string trailer;
  ByteWriter w(trailer);
  w.u32(0);
  w.u32(impl_->frames);
  impl_->sink.write(trailer);
  impl_->sink.finish();
}

// --- reading -----------------------------------------------------------------------------------

namespace {

class ByteReader {
 public:
  ByteReader(const std::string& data, std::string name) : data_(data), name_(std::move(name)) {}
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(name_ + ": malformed recording: " + what);
  }
  std::size_t pos() const { return pos_; }
  std::size_t left() const { return data_.size() - pos_; }
  void need(std::size_t n, const char* what) const {
    if (n > left()) fail(std::string("truncated in ") + what);
  }
  std::uint64_t bytes(int n, const char* what) {
    need(n, what);
    std::uint64_t v = 0;
    for (int i = 0; i < n; ++i) v |= std::uint64_t(static_cast<unsigned char>(data_[pos_ + i])) << (8 * i);
    pos_ += n;
    return v;
  }
  std::uint8_t u8(const char* what) { return static_cast<std::uint8_t>(bytes(1, what)); }
  std::uint16_t u16(const char* what) { return static_cast<std::uint16_t>(bytes(2, what)); }
  std::uint32_t u32(const char* what) { return static_cast<std::uint32_t>(bytes(4, what)); }
  std::int32_t i32(const char* what) { return static_cast<std::int32_t>(u32(what)); }
  float f32(const char* what) {
    const std::uint32_t bits = u32(what);
    float v;
    std::memcpy(&v, &bits, 4);
    return v;
  }
  double f64(const char* what) {
    const std::uint64_t bits = bytes(8, what);
    double v;
    std::memcpy(&v, &bits, 8);
    return v;
  }
  std::string text(std::size_t n, const char* what) {
    need(n, what);
    std::string s = data_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  void pad4(const char* what) {
    while (pos_ % 4) u8(what);
  }
  // A count of items of `item_bytes` each that must still fit in the data (guards allocations).
  std::uint32_t count(std::size_t item_bytes, const char* what) {
    const std::uint32_t n = u32(what);
    if (std::uint64_t(n) * item_bytes > left()) fail(std::string("impossible count of ") + what);
    return n;
  }

 private:
  const std::string& data_;
  std::string name_;
  std::size_t pos_ = 0;
};

std::string gunzip(const std::string& in, const std::string& name) {
  if (in.size() < 2 || in[0] != '\x1f' || in[1] != '\x8b')
    throw InputError(name + ": not an rbpart recording (not gzip-compressed data)");
  z_stream z{};
  // windowBits 15 + 16: gzip only; anything else is not a recording.
  if (inflateInit2(&z, 15 + 16) != Z_OK) throw std::runtime_error("recording: inflateInit2 failed");
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data()));
  z.avail_in = static_cast<uInt>(in.size());
  std::string out;
  char buffer[1 << 16];
  int ret;
  do {
    z.next_out = reinterpret_cast<Bytef*>(buffer);
    z.avail_out = sizeof(buffer);
    ret = inflate(&z, Z_NO_FLUSH);
    out.append(buffer, sizeof(buffer) - z.avail_out);
  } while (ret == Z_OK);
  inflateEnd(&z);
  if (ret == Z_STREAM_END) return out;
  if (ret == Z_BUF_ERROR) throw InputError(name + ": malformed recording: the gzip stream is truncated");
  throw InputError(name + ": not an rbpart recording (not gzip-compressed data)");
}

RecordedChannel read_channel(ByteReader& r, std::size_t nodes, std::size_t edges) {
  RecordedChannel c;
  c.parts = r.u32("channel");
  c.edge_cut = r.u32("channel");
  c.interface_rows = r.u32("channel");
  c.interface_bodies = r.u32("channel");
  c.partition_ms = r.f32("channel");
  c.refine_ms = r.f32("channel");
  r.need(4 * nodes, "part ids");
  c.part_of.resize(nodes);
  for (auto& p : c.part_of) {
    p = r.u32("part ids");
    if (p >= c.parts) r.fail("part id out of range");
  }
  c.interface.resize((edges + 7) / 8);
  for (auto& b : c.interface) b = r.u8("interface bits");
  r.pad4("interface bits");
  return c;
}

}  // namespace

std::vector<std::string> Recording::channel_names() const {
  std::vector<std::string> names;
  for (const auto& c : meta.at("channels")) names.push_back(c.at("name").get<std::string>());
  return names;
}

Recording parse_recording(const std::string& gzip_bytes, const std::string& name) {
  const std::string data = gunzip(gzip_bytes, name);
  if (data.size() < kRecordingMagic.size() ||
      data.compare(0, kRecordingMagic.size(), kRecordingMagic.data(), kRecordingMagic.size()) != 0)
    throw InputError(name + ": not an rbpart recording (bad magic)");
  ByteReader r(data, name);
  r.text(kRecordingMagic.size(), "magic");
  const std::uint32_t version = r.u32("header");
  if (version != kRecordingVersion)
    throw InputError(name + ": recording format version " + std::to_string(version) + " (this rbpart reads " +
                     std::to_string(kRecordingVersion) + ")");
  Recording rec;
  const std::uint32_t meta_bytes = r.u32("header");
  try {
    rec.meta = nlohmann::json::parse(r.text(meta_bytes, "header"));
  } catch (const nlohmann::json::exception&) {
    r.fail("the header is not JSON");
  }
  std::size_t body_count = 0, channel_count = 0, stat_count = 0;
  try {
    // A count: get<std::size_t>() of a negative or fractional number (1e300) converts it unchecked.
    const nlohmann::json& bodies = rec.meta.at("bodies");
    if (!bodies.is_number_unsigned()) r.fail("header: bodies is not a count (got " + bodies.dump() + ")");
    body_count = bodies.get<std::size_t>();
    channel_count = rec.meta.at("channels").size();
    stat_count = rec.meta.at("stats").size();
    for (const auto& c : rec.meta.at("channels")) c.at("name").get<std::string>();
  } catch (const nlohmann::json::exception& e) {
    r.fail(std::string("header: ") + e.what());
  }
  if (channel_count == 0) r.fail("no partition channel");
  if (body_count > r.left() / 48) r.fail("impossible body count");  // 48 bytes = smallest body record

  rec.bodies.resize(body_count);
  for (std::size_t i = 0; i < body_count; ++i) {
    RecordedBody& b = rec.bodies[i];
    const std::uint8_t code = r.u8("shapes");
    b.is_static = r.u8("shapes") != 0;
    r.u16("shapes");
    for (float& x : b.pose) x = r.f32("shapes");
    b.mass = r.f32("shapes");
    for (float& x : b.com) x = r.f32("shapes");
    Shape& s = b.shape;
    switch (code) {
      case kSphere:
        s.type = ShapeType::Sphere;
        s.radius = r.f32("shapes");
        break;
      case kBox:
        s.type = ShapeType::Box;
        for (int k = 0; k < 3; ++k) s.half_extents[k] = r.f32("shapes");
        break;
      case kCapsule:
      case kCylinder:
        s.type = code == kCapsule ? ShapeType::Capsule : ShapeType::Cylinder;
        s.radius = r.f32("shapes");
        s.half_length = r.f32("shapes");
        break;
      case kConvex: {
        s.type = ShapeType::Convex;
        const std::uint32_t nv = r.u32("hull"), nf = r.u32("hull"), ni = r.u32("hull");
        r.need(std::uint64_t(nv) * 12 + (std::uint64_t(nf) + 1 + ni) * 4, "hull");
        s.vertices.resize(nv);
        for (Vec3& v : s.vertices)
          for (int k = 0; k < 3; ++k) v[k] = r.f32("hull");
        b.face_offsets.resize(nf + 1);
        for (auto& o : b.face_offsets) o = r.u32("hull");
        b.face_indices.resize(ni);
        for (auto& x : b.face_indices)
          if ((x = r.u32("hull")) >= nv) r.fail("hull vertex index out of range");
        for (std::uint32_t f = 0; f < nf; ++f)
          if (b.face_offsets[f] > b.face_offsets[f + 1]) r.fail("hull face offsets decrease");
        if (b.face_offsets.front() != 0 || b.face_offsets.back() != ni) r.fail("hull face offsets");
        break;
      }
      default: r.fail("unknown shape code " + std::to_string(code));
    }
    if (!b.is_static) rec.body_of.push_back(static_cast<int>(i));
  }
  const std::size_t nodes = rec.body_of.size();

  for (;;) {
    const std::uint32_t length = r.u32("frame length");
    if (length == 0) break;
    if (length % 4 || length > r.left()) r.fail("frame " + std::to_string(rec.frames.size() + 1) + " is truncated");
    const std::size_t end = r.pos() + length;
    RecordedFrame f;
    f.step = r.i32("frame");
    f.time = r.f64("frame");
    f.stats.resize(stat_count);
    for (double& x : f.stats) x = r.f64("frame stats");
    r.need(28 * nodes, "poses");
    f.poses.resize(7 * nodes);
    for (float& x : f.poses) x = r.f32("poses");
    const std::uint32_t edges = r.count(12, "edges");
    f.edge_u.resize(edges);
    f.edge_v.resize(edges);
    f.edge_weight.resize(edges);
    f.edge_rows.resize(edges);
    for (auto& u : f.edge_u) u = r.u32("edges");
    for (auto& v : f.edge_v) v = r.u32("edges");
    for (auto& x : f.edge_weight) x = r.u16("edges");
    for (auto& x : f.edge_rows) x = r.u16("edges");
    r.pad4("edges");
    for (std::uint32_t e = 0; e < edges; ++e)
      if (f.edge_u[e] >= f.edge_v[e] || f.edge_v[e] >= nodes) r.fail("edge node out of range");
    for (std::size_t c = 0; c < channel_count; ++c) f.channels.push_back(read_channel(r, nodes, edges));
    if (r.pos() != end) r.fail("frame " + std::to_string(rec.frames.size() + 1) + " has the wrong length");
    rec.frames.push_back(std::move(f));
  }
  if (r.u32("trailer") != rec.frames.size()) r.fail("the trailer's frame count does not match");
  if (r.left() != 0) r.fail("data after the trailer");
  return rec;
}

Recording read_recording(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot read");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return parse_recording(bytes.str(), path);
}

}  // namespace rbpart
