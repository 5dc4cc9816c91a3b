// Recordings (docs/recording.md): what a World did is read back exactly (at float precision), the
// interface edges of every channel are those joining different parts, and malformed files are
// refused with a message naming the problem.
#include "io/recording.hpp"

#include "core/error.hpp"
#include "geometry/hull.hpp"
#include "graph/constraint_graph.hpp"
#include "io/temp_dir.hpp"
#include "partition/partition.hpp"
#include "scene/bodies.hpp"
#include "step/world_internals.hpp"

#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <fstream>

namespace rbpart {
namespace {

BodyDef body(const std::string& name, ShapeType type, const Vec3& position) {
  BodyDef b;
  b.name = name;
  b.shape.type = type;
  b.position = position;
  b.density = 1000;
  return b;
}

// Every shape type, resting from the start: a stack box-box-sphere (a three-body island with two
// edges) and, apart, a standing capsule, a standing cylinder and a convex cube (one body each).
SceneDef all_shapes_scene() {
  SceneDef s;
  s.name = "all shapes";
  BodyDef ground = body("ground", ShapeType::Box, Vec3(0, 0, -0.5));
  ground.is_static = true;
  ground.shape.half_extents = Vec3(6, 6, 0.5);
  ground.orientation = Quat(Eigen::AngleAxisd(0.01, Vec3::UnitX()));
  s.bodies.push_back(ground);
  for (int k = 0; k < 2; ++k) {
    BodyDef box = body("box" + std::to_string(k), ShapeType::Box, Vec3(0, 0, 0.5 + k));
    box.shape.half_extents = Vec3(0.5, 0.5, 0.5);
    s.bodies.push_back(box);
  }
  BodyDef sphere = body("sphere", ShapeType::Sphere, Vec3(0, 0, 2.3));
  sphere.shape.radius = 0.3;
  s.bodies.push_back(sphere);
  BodyDef capsule = body("capsule", ShapeType::Capsule, Vec3(3, 0, 0.5));
  capsule.shape.radius = 0.2;
  capsule.shape.half_length = 0.3;
  s.bodies.push_back(capsule);
  BodyDef cylinder = body("cylinder", ShapeType::Cylinder, Vec3(-3, 0, 0.25));
  cylinder.shape.radius = 0.3;
  cylinder.shape.half_length = 0.25;
  s.bodies.push_back(cylinder);
  // A cube's corners plus a point inside it, which the hull leaves out; turned about z.
  BodyDef convex = body("convex", ShapeType::Convex, Vec3(0, 3, 0.25));
  for (int i = 0; i < 8; ++i)
    convex.shape.vertices.emplace_back(i & 1 ? 0.25 : -0.25, i & 2 ? 0.25 : -0.25, i & 4 ? 0.25 : -0.25);
  convex.shape.vertices.emplace_back(0.05, 0, 0);
  convex.orientation = Quat(Eigen::AngleAxisd(0.3, Vec3::UnitZ()));
  s.bodies.push_back(convex);
  return s;
}

// The world's state after one step, as the recording should hold it.
struct Expected {
  int step;
  double time;
  std::vector<float> poses;
  std::vector<int> eu, ev, weight, rows;
  std::vector<int> part_of;
  int parts;
};

Expected expect(const World& world) {
  Expected e{world.step_count(), world.time(), {}, {}, {}, {}, {}, world_partition(world).part_of,
             world_partition(world).part_count};
  const ConstraintGraph& g = world_graph(world);
  for (int node = 0; node < g.node_count(); ++node) {
    const int i = g.body_of[node];
    const Vec3 p = world_bodies(world).frame_position(i);
    const Quat& q = world_bodies(world).q[i];
    for (double x : {p.x(), p.y(), p.z(), q.w(), q.x(), q.y(), q.z()}) e.poses.push_back(static_cast<float>(x));
    for (int k = g.offset[node]; k < g.offset[node + 1]; ++k)
      if (g.adjacency[k] > node) {
        e.eu.push_back(node);
        e.ev.push_back(g.adjacency[k]);
        e.weight.push_back(g.weight[k]);
        e.rows.push_back(g.rows[k]);
      }
  }
  return e;
}

class RecordingTest : public ::testing::Test {
 protected:
  void record(const std::string& path, int steps, const std::string& extra = "") {
    World world(all_shapes_scene());
    PartitionParams base;
    base.nmax = 2;
    const std::vector<PartitionParams> channels = parse_channel_list(extra, base);
    std::vector<ChannelPartition> parts(channels.size());
    RecordingWriter writer(path, world, {{"solver", "direct"}}, "islands", channels);
    for (int i = 0; i < steps; ++i) {
      const StepStats& s = world.step();
      for (std::size_t c = 0; c < channels.size(); ++c)
        parts[c].quality = partition_and_refine(world_graph(world), channels[c], parts[c].partition);
      writer.write_step(world, s, parts);
      expected.push_back(expect(world));
      stats.push_back(s);
    }
    writer.finish();
  }
  test::TempDir dir;
  std::vector<Expected> expected;
  std::vector<StepStats> stats;
};

TEST_F(RecordingTest, ShapesAndStartPosesRoundTrip) {
  const std::string path = dir.file("run.rbrec");
  record(path, 1);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"run.rbrec"});
  const Recording rec = read_recording(path);
  const SceneDef scene = all_shapes_scene();
  EXPECT_EQ(rec.meta.at("scene"), "all shapes");
  EXPECT_EQ(rec.meta.at("dt").get<double>(), scene.dt);
  EXPECT_EQ(rec.meta.at("params").at("solver"), "direct");
  EXPECT_EQ(rec.meta.at("stats").get<std::vector<std::string>>(), kRecordedStats);
  EXPECT_EQ(rec.channel_names(), std::vector<std::string>{"islands"});
  ASSERT_EQ(rec.bodies.size(), scene.bodies.size());
  EXPECT_EQ(rec.body_of, (std::vector<int>{1, 2, 3, 4, 5, 6}));
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const BodyDef& def = scene.bodies[i];
    const RecordedBody& b = rec.bodies[i];
    EXPECT_EQ(b.is_static, def.is_static);
    EXPECT_EQ(b.shape.type, def.shape.type);
    EXPECT_EQ(b.shape.radius, static_cast<float>(def.shape.radius));
    EXPECT_EQ(b.shape.half_length, static_cast<float>(def.shape.half_length));
    for (int k = 0; k < 3; ++k) EXPECT_EQ(b.shape.half_extents[k], static_cast<float>(def.shape.half_extents[k]));
    // The start pose is the scene's shape frame (the centre of mass moved back by com).
    const Quat q = def.orientation.normalized();
    const float pose[7] = {float(def.position.x()), float(def.position.y()), float(def.position.z()),
                           float(q.w()), float(q.x()), float(q.y()), float(q.z())};
    for (int k = 0; k < 7; ++k) EXPECT_NEAR(b.pose[k], pose[k], 1e-6) << "body " << i << " pose " << k;
    // Centre of mass of a symmetric shape: the frame origin.
    if (def.shape.type != ShapeType::Convex) {
      for (int k = 0; k < 3; ++k) EXPECT_EQ(b.com[k], 0.0f);
    }
  }
  // Box mass = density x volume.
  EXPECT_FLOAT_EQ(rec.bodies[1].mass, 1000.0f);
  EXPECT_EQ(rec.bodies[0].mass, 0.0f);
  // The convex body: its points, and the hull faces of a cube (6 quadrilaterals), which leave out
  // the inner point 8 and are the collider's faces.
  const RecordedBody& cube = rec.bodies[6];
  ASSERT_EQ(cube.shape.vertices.size(), 9u);
  EXPECT_EQ(cube.shape.vertices[8].cast<float>(), Eigen::Vector3f(0.05f, 0, 0));
  const HullFaces hull = convex_hull_faces(scene.bodies[6].shape.vertices);
  EXPECT_EQ(cube.face_offsets, std::vector<std::uint32_t>(hull.offsets.begin(), hull.offsets.end()));
  EXPECT_EQ(cube.face_indices, std::vector<std::uint32_t>(hull.indices.begin(), hull.indices.end()));
  EXPECT_EQ(cube.face_offsets.size(), 7u);
  EXPECT_EQ(cube.face_indices.size(), 24u);
  for (auto i : cube.face_indices) EXPECT_NE(i, 8u);
  // The cube's centre of mass: the inner point does not move it off the origin.
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(cube.com[k], 0.0f, 1e-6);
}

TEST_F(RecordingTest, FramesHoldPosesGraphAndStats) {
  const std::string path = dir.file("run.rbrec");
  record(path, 5);
  const Recording rec = read_recording(path);
  ASSERT_EQ(rec.frames.size(), 5u);
  for (std::size_t f = 0; f < rec.frames.size(); ++f) {
    const RecordedFrame& fr = rec.frames[f];
    const Expected& e = expected[f];
    EXPECT_EQ(fr.step, static_cast<int>(f) + 1);
    EXPECT_EQ(fr.time, e.time);
    EXPECT_EQ(fr.poses, e.poses);
    EXPECT_EQ(std::vector<int>(fr.edge_u.begin(), fr.edge_u.end()), e.eu);
    EXPECT_EQ(std::vector<int>(fr.edge_v.begin(), fr.edge_v.end()), e.ev);
    EXPECT_EQ(std::vector<int>(fr.edge_weight.begin(), fr.edge_weight.end()), e.weight);
    EXPECT_EQ(std::vector<int>(fr.edge_rows.begin(), fr.edge_rows.end()), e.rows);
    // Stats by name.
    const auto stat = [&](const std::string& name) {
      const auto it = std::find(kRecordedStats.begin(), kRecordedStats.end(), name);
      return fr.stats.at(it - kRecordedStats.begin());
    };
    EXPECT_EQ(stat("contacts"), stats[f].contacts);
    EXPECT_EQ(stat("rows"), stats[f].rows);
    EXPECT_EQ(stat("solve_ms"), stats[f].profile.solve_ms);
    EXPECT_EQ(stat("kinetic_energy"), stats[f].kinetic_energy);
    EXPECT_EQ(stat("island_factorizations"), stats[f].solve.island_factorizations);
    // Channel 0: the run's islands: {box0, box1, sphere} and three single bodies, no interface.
    ASSERT_EQ(fr.channels.size(), 1u);
    const RecordedChannel& c = fr.channels[0];
    EXPECT_EQ(std::vector<int>(c.part_of.begin(), c.part_of.end()), e.part_of);
    EXPECT_EQ(c.parts, 4u);
    EXPECT_EQ(c.edge_cut, 0u);
    EXPECT_EQ(c.interface_rows, 0u);
    EXPECT_EQ(c.interface_bodies, 0u);
  }
  // The stack rests on its first step: two edges, box0-box1 (a face on a face: at least 3 contact
  // points) and box1-sphere (one point).
  const RecordedFrame& first = rec.frames[0];
  ASSERT_EQ(first.edge_u.size(), 2u);
  EXPECT_EQ(first.edge_u[0], 0u);
  EXPECT_EQ(first.edge_v[0], 1u);
  EXPECT_GE(first.edge_weight[0], 3);
  EXPECT_EQ(first.edge_u[1], 1u);
  EXPECT_EQ(first.edge_v[1], 2u);
  EXPECT_EQ(first.edge_weight[1], 1);
}

// A recorder channel with nmax 2 splits the three-body stack: BFS from box0 takes box0 and box1,
// the sphere is a part of its own, so box1-sphere is the one interface edge.
TEST_F(RecordingTest, ExtraChannelMarksInterfaceEdges) {
  const std::string path = dir.file("run.rbrec");
  record(path, 2, "bfs,mindp+fm");
  const Recording rec = read_recording(path);
  EXPECT_EQ(rec.channel_names(), (std::vector<std::string>{"islands", "bfs", "mindp+fm"}));
  EXPECT_EQ(rec.meta.at("channels")[1].at("nmax"), 2);
  EXPECT_EQ(rec.meta.at("channels")[2].at("refiner"), "fm");
  for (const RecordedFrame& fr : rec.frames) {
    ASSERT_EQ(fr.channels.size(), 3u);
    ASSERT_EQ(fr.edge_u.size(), 2u);
    const RecordedChannel& bfs = fr.channels[1];
    EXPECT_EQ(bfs.part_of[0], bfs.part_of[1]);
    EXPECT_NE(bfs.part_of[1], bfs.part_of[2]);
    EXPECT_FALSE(bfs.is_interface(0));
    EXPECT_TRUE(bfs.is_interface(1));
    EXPECT_EQ(bfs.parts, 5u);
    EXPECT_EQ(bfs.edge_cut, fr.edge_weight[1]);
    EXPECT_EQ(bfs.interface_rows, fr.edge_rows[1]);
    EXPECT_EQ(bfs.interface_bodies, 2u);
    // Whatever the partition, the bits mark exactly the edges between different parts.
    for (const RecordedChannel& c : fr.channels)
      for (std::size_t e = 0; e < fr.edge_u.size(); ++e)
        EXPECT_EQ(c.is_interface(e), c.part_of[fr.edge_u[e]] != c.part_of[fr.edge_v[e]]);
  }
}

TEST_F(RecordingTest, UnfinishedRecordingLeavesNoFile) {
  {
    World world(all_shapes_scene());
    RecordingWriter writer(dir.file("run.rbrec"), world, {}, "islands", {});
    writer.write_step(world, world.step(), {});
  }
  EXPECT_TRUE(dir.entries().empty());
}

TEST(RecordingChannels, ParsesTheListAndRefusesBadItems) {
  PartitionParams base;
  base.nmax = 7;
  const auto channels = parse_channel_list("mindp,mix+fm,bfs", base);
  ASSERT_EQ(channels.size(), 3u);
  EXPECT_EQ(channel_name(channels[0]), "mindp");
  EXPECT_EQ(channel_name(channels[1]), "mix+fm");
  EXPECT_EQ(channels[1].refiner, RefinerKind::Fm);
  EXPECT_EQ(channels[2].nmax, 7);
  EXPECT_TRUE(parse_channel_list("", base).empty());
  EXPECT_THROW(parse_channel_list("mindp,,bfs", base), InputError);
  EXPECT_THROW(parse_channel_list("mindp,", base), InputError);
  EXPECT_THROW(parse_channel_list("nosuch", base), InputError);
  EXPECT_THROW(parse_channel_list("bfs+nosuch", base), InputError);
  EXPECT_THROW(parse_channel_list("none", base), InputError);
}

std::string gzip(const std::string& data) {
  std::string out(compressBound(data.size()) + 64, '\0');
  z_stream z{};
  deflateInit2(&z, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY);
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
  z.avail_in = data.size();
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = out.size();
  deflate(&z, Z_FINISH);
  out.resize(z.total_out);
  deflateEnd(&z);
  return out;
}

std::string gunzip(const std::string& data) {
  std::string out(1 << 22, '\0');
  z_stream z{};
  inflateInit2(&z, 15 + 16);
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
  z.avail_in = data.size();
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = out.size();
  inflate(&z, Z_FINISH);
  out.resize(z.total_out);
  inflateEnd(&z);
  return out;
}

std::string error_of(const std::string& bytes) {
  try {
    parse_recording(bytes, "f.rbrec");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST_F(RecordingTest, MalformedRecordingsAreRefusedByName) {
  const std::string path = dir.file("run.rbrec");
  record(path, 2);
  const std::string good = test::read_text(path);
  const std::string raw = gunzip(good);
  ASSERT_EQ(gzip(raw).empty(), false);
  ASSERT_EQ(error_of(gzip(raw)), "no error");

  EXPECT_EQ(error_of("plain text, not gzip"), "f.rbrec: not an rbpart recording (not gzip-compressed data)");
  EXPECT_EQ(error_of(good.substr(0, good.size() / 2)), "f.rbrec: malformed recording: the gzip stream is truncated");
  EXPECT_EQ(error_of(gzip("RBPREC\n\n" + raw.substr(8))), "f.rbrec: not an rbpart recording (bad magic)");
  std::string v2 = raw;
  v2[8] = 2;
  EXPECT_EQ(error_of(gzip(v2)), "f.rbrec: recording format version 2 (this rbpart reads 1)");
  // Cut inside the last frame, or the trailer missing: both truncated, in the data itself.
  EXPECT_NE(error_of(gzip(raw.substr(0, raw.size() - 40))).find("truncated"), std::string::npos);
  // The trailer's count disagreeing with the frames.
  std::string miscounted = raw;
  miscounted[raw.size() - 4] = 3;
  EXPECT_EQ(error_of(gzip(miscounted)), "f.rbrec: malformed recording: the trailer's frame count does not match");
  // A part id beyond the part count: the last channel's first id (after the frame's edges).
  std::string bad_part = raw;
  const Recording parsed = parse_recording(good, "f");  // kept: `last` refers into it
  const RecordedFrame& last = parsed.frames.back();
  const std::size_t channel_bytes = 24 + 4 * last.channels[0].part_of.size() + ((last.edge_u.size() + 7) / 8 + 3) / 4 * 4;
  const std::size_t first_id = raw.size() - 8 - channel_bytes + 24;
  bad_part[first_id] = 100;
  EXPECT_EQ(error_of(gzip(bad_part)), "f.rbrec: malformed recording: part id out of range");
  EXPECT_EQ(error_of(""), "f.rbrec: not an rbpart recording (not gzip-compressed data)");
  EXPECT_THROW(read_recording(dir.file("missing.rbrec")), InputError);
}

}  // namespace
}  // namespace rbpart
