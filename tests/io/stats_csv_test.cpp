// Stats CSV: the column header on line 1, one exact line per step, the parameters in a JSON sidecar;
// both written atomically.
#include "io/stats_csv.hpp"

#include "core/error.hpp"
#include "io/temp_dir.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <map>

#include <cstdlib>
#include <sstream>

namespace rbpart {
namespace {

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(text);
  while (std::getline(in, part, separator)) parts.push_back(part);
  return parts;
}

// Every field distinct, so a value in the wrong column is caught.
StepStats numbered_stats() {
  StepStats s;
  s.step = 1;
  s.bodies = 2;
  s.contacts = 3;
  s.rows = 4;
  s.islands = 5;
  s.partition.parts = 6;
  s.partition.interface_rows = 7;
  s.partition.interface_bodies = 8;
  s.partition.edge_cut = 9;
  s.profile = {10.5, 11.5, 12.5, 13.5, 14.5, 15.5, 16.5, 17.5, 18.5};
  s.solve.iterations = 19;
  s.solve.factorizations = 20;
  s.solve.residual = 1.0 / 3.0 * 1e-12;
  s.max_penetration = 0.1 + 0.2;
  s.kinetic_energy = 2.0 / 7.0 * 1e3;
  s.solve.factor_ms = 24.5;
  s.solve.work_ms = 25.5;
  s.solve.critical_path_ms = 26.5;
  s.solve.unsettled = 27;
  s.solve.island_factorizations = 28;
  return s;
}

TEST(StatsCsv, HeaderThenOneExactLinePerStep) {
  test::TempDir dir;
  const std::string path = dir.file("stats.csv");
  StatsCsvWriter writer(path, {{"erp", "0.2"}, {"scene", "two\nlines"}});
  StepStats first = numbered_stats();
  writer.write(first);
  StepStats second;
  second.step = 2;
  second.profile.solve_ms = 1.23456789;
  second.max_penetration = -0.0;
  writer.write(second);
  // Nothing is visible before finish().
  EXPECT_EQ(dir.entries().size(), 2u);
  for (const std::string& name : dir.entries()) EXPECT_TRUE(name != "stats.csv" && name != "stats.csv.json") << name;
  writer.finish();
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"stats.csv", "stats.csv.json"}));

  // The parameters, in the sidecar only, with their text as given (a line break included).
  const nlohmann::ordered_json params = nlohmann::ordered_json::parse(test::read_text(dir.file("stats.csv.json")));
  EXPECT_EQ(params, (nlohmann::ordered_json{{"erp", "0.2"}, {"scene", "two\nlines"}}));
  EXPECT_EQ(params.begin().key(), "erp");

  // Line 1 is the header: no comment lines.
  const std::vector<std::string> lines = split(test::read_text(path), '\n');
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0],
            "step,bodies,contacts,rows,islands,parts,interface_rows,interface_bodies,edge_cut,collide_ms,"
            "assemble_ms,graph_ms,partition_ms,refine_ms,solve_ms,integrate_ms,project_ms,total_ms,solver_iterations,"
            "factorizations,blcp_residual,max_penetration,kinetic_energy,factor_ms,work_ms,critical_path_ms,"
            "unsettled,island_factorizations");
  EXPECT_EQ(split(lines[0], ',').size(), StatsCsvWriter::kColumns.size());

  // Row 1: columns 1..20 and 24..28 hold their own number (the times n + 0.5), 21..23 are exact.
  const std::vector<std::string> row = split(lines[1], ',');
  ASSERT_EQ(row.size(), StatsCsvWriter::kColumns.size());
  for (int c = 0; c < static_cast<int>(row.size()); ++c) {
    if (c >= 20 && c <= 22) continue;
    const double expected = ((c >= 9 && c <= 17) || (c >= 23 && c <= 25)) ? c + 1.5 : c + 1;
    EXPECT_EQ(std::strtod(row[c].c_str(), nullptr), expected) << StatsCsvWriter::kColumns[c];
  }
  EXPECT_EQ(std::strtod(row[20].c_str(), nullptr), first.solve.residual);
  EXPECT_EQ(std::strtod(row[21].c_str(), nullptr), first.max_penetration);
  EXPECT_EQ(std::strtod(row[22].c_str(), nullptr), first.kinetic_energy);

  // Row 2: times to six significant digits; the sign of a zero is kept.
  const std::vector<std::string> row2 = split(lines[2], ',');
  ASSERT_EQ(row2.size(), StatsCsvWriter::kColumns.size());
  EXPECT_EQ(row2[0], "2");
  EXPECT_EQ(row2[14], "1.23457");
  EXPECT_EQ(row2[21], "-0");
}

TEST(StatsCsv, AbandonedWriterLeavesNothing) {
  test::TempDir dir;
  {
    StatsCsvWriter writer(dir.file("stats.csv"), {});
    writer.write(numbered_stats());
  }
  EXPECT_TRUE(dir.entries().empty());
}

TEST(StatsCsv, SidecarPathIsTheCsvPathWithJsonAppended) {
  EXPECT_EQ(StatsCsvWriter::sidecar_path("out/run.csv"), "out/run.csv.json");
}

TEST(StatsCsv, UnwritablePathIsAnInputError) {
  test::TempDir dir;
  EXPECT_THROW(StatsCsvWriter(dir.file("no/such/dir/stats.csv"), {}), InputError);
  EXPECT_TRUE(dir.entries().empty());
}

// Every parameter is reported under its name, and a changed value reads back exactly.
TEST(RunParameters, EveryParameterByNameAndExact) {
  StepParams step;
  SolverParams solver;
  step.erp = 1.0 / 3.0;
  step.slop = 0.1 + 0.2;
  step.joint_projection_iterations = 7;
  solver.kind = SolverKind::Pgs;
  solver.pgs_iterations = 12345;
  std::map<std::string, std::string> by_name;
  for (const auto& [name, value] : run_parameters(step, solver)) by_name[name] = value;
  for (const char* name : {"erp", "slop", "sigma_floor", "contact_prox", "sliding_velocity_eps", "contact_margin",
                           "joint_projection_iterations", "joint_tolerance", "projection_depth", "projection_turn",
                           "solver", "max_factorizations", "pgs_iterations", "pgs_tolerance",
                           "threads"})
    EXPECT_EQ(by_name.count(name), 1u) << name;
  EXPECT_EQ(std::strtod(by_name["erp"].c_str(), nullptr), 1.0 / 3.0);
  EXPECT_EQ(std::strtod(by_name["slop"].c_str(), nullptr), 0.1 + 0.2);
  EXPECT_EQ(by_name["joint_projection_iterations"], "7");
  EXPECT_EQ(by_name["solver"], "pgs");
  EXPECT_EQ(by_name["pgs_iterations"], "12345");
}

}  // namespace
}  // namespace rbpart
