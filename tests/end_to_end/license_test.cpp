// The repository carries its licence: MIT, copyright the rbpart developers.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

namespace {

TEST(License, TheRepositoryIsMitLicensedByTheRbpartDevelopers) {
  std::ifstream in(std::string(RBPART_SOURCE_DIR) + "/LICENSE");
  ASSERT_TRUE(in) << "no LICENSE file";
  std::stringstream text;
  text << in.rdbuf();
  const std::string license = text.str();
  EXPECT_EQ(license.rfind("MIT License\n", 0), 0u);
  EXPECT_NE(license.find("Copyright (c) 2026 the rbpart developers\n"), std::string::npos);
  EXPECT_NE(license.find("THE SOFTWARE IS PROVIDED \"AS IS\", WITHOUT WARRANTY OF ANY KIND"), std::string::npos);
}

}  // namespace
