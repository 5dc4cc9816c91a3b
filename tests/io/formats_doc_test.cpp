// The examples of docs/formats.md, read by the readers they document: a scene file that loads and
// runs, and a METIS graph with edge weights. A change of either format must change the page too.
#include <rbpart/world.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "io/metis_graph.hpp"
#include "io/scene_json.hpp"
#include "scene/bodies.hpp"
#include "step/world_internals.hpp"

namespace rbpart {
namespace {

// The first fenced block after `<a id="anchor">` in docs/formats.md, without its fences.
std::string example_after(const std::string& anchor) {
  std::ifstream in(std::string(RBPART_SOURCE_DIR) + "/docs/formats.md");
  std::stringstream page;
  page << in.rdbuf();
  const std::string text = page.str();
  const std::size_t at = text.find("<a id=\"" + anchor + "\">");
  EXPECT_NE(at, std::string::npos) << "no anchor " << anchor;
  if (at == std::string::npos) return "";
  const std::size_t fence = text.find("```", at);
  const std::size_t body = text.find('\n', fence) + 1;
  const std::size_t end = text.find("\n```", body);
  EXPECT_NE(end, std::string::npos) << "unterminated block after " << anchor;
  return text.substr(body, end + 1 - body);
}

TEST(FormatsDoc, TheSceneFileExampleLoadsWithTheDocumentedDefaultsAndRuns) {
  const SceneDef scene = parse_scene(example_after("scene-file"), "docs/formats.md");
  EXPECT_EQ(scene.name, "example");
  EXPECT_EQ(scene.dt, 0.01);
  EXPECT_EQ(scene.steps, 300);
  ASSERT_EQ(scene.bodies.size(), 4u);
  ASSERT_EQ(scene.joints.size(), 2u);
  EXPECT_TRUE(scene.bodies[0].is_static);
  EXPECT_EQ(scene.bodies[1].mass, 1.0);
  EXPECT_EQ(scene.bodies[1].friction, -1.0);  // the scene's default applies
  EXPECT_EQ(scene.bodies[3].friction, 0.2);
  EXPECT_EQ(scene.bodies[3].shape.type, ShapeType::Capsule);
  EXPECT_NEAR(scene.bodies[1].orientation.norm(), 1.0, 1e-12);
  EXPECT_EQ(scene.joints[0].type, JointType::Hinge);
  EXPECT_EQ(scene.joints[0].body_b, -1);
  EXPECT_EQ(scene.joints[1].type, JointType::Ball);
  EXPECT_EQ(scene.joints[1].compliance, 1e-7);
  EXPECT_FALSE(scene.joints[1].collide_connected);

  // As the page says: the box lands on the floor and stays on it, the pendulum swings on its hinge.
  World world(scene);
  for (int i = 0; i < 100; ++i) world.step();
  const Bodies& b = world_bodies(world);
  EXPECT_NEAR(b.frame_position(1).z(), 0.2, 2e-3);
  EXPECT_NEAR((b.frame_position(2) - Vec3(1, 0, 2.5)).norm(), 0.5, 1e-3);
  for (int i = 0; i < b.size(); ++i) EXPECT_TRUE(b.frame_position(i).allFinite()) << i;
}

TEST(FormatsDoc, TheMetisExampleIsTheGridItDescribes) {
  std::istringstream in(example_after("metis-graph"));
  const MetisGraph m = parse_metis_graph(in, "docs/formats.md");
  ASSERT_EQ(m.graph.node_count(), 6);
  EXPECT_EQ(m.graph.edge_count(), 7);
  // Vertex 2's neighbours 1, 3, 5 (0-based 0, 2, 4), the edge to 5 weighted 2.
  const int first = m.graph.offset[1];
  ASSERT_EQ(m.graph.offset[2] - first, 3);
  EXPECT_EQ(m.graph.adjacency[first + 2], 4);
  EXPECT_EQ(m.graph.weight[first + 2], 2);
  EXPECT_EQ(m.graph.degree(4), 4);
}

}  // namespace
}  // namespace rbpart
