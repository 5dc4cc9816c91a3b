// Atomic output: a file appears complete or not at all, and never leaves a temporary behind.
#include "io/atomic_file.hpp"

#include "core/error.hpp"
#include "io/temp_dir.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>

namespace rbpart {
namespace {

TEST(AtomicFile, CommitReplacesTheTargetWhole) {
  test::TempDir dir;
  const std::string path = dir.file("out.txt");
  write_file_atomically(path, "old contents that are longer\n");
  AtomicFile file(path);
  file.write("new ");
  file.write("text\n");
  // Until the commit, the old file is intact next to the temporary one.
  EXPECT_EQ(test::read_text(path), "old contents that are longer\n");
  EXPECT_EQ(dir.entries().size(), 2u);
  file.commit();
  EXPECT_EQ(test::read_text(path), "new text\n");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"out.txt"});
  EXPECT_THROW(file.commit(), std::logic_error);
}

TEST(AtomicFile, UncommittedFileIsRemoved) {
  test::TempDir dir;
  {
    AtomicFile file(dir.file("out.txt"));
    file.write("partial");
  }
  EXPECT_TRUE(dir.entries().empty());
}

// Tests run as root here, so a read-only directory would not stop them: use paths whose directory
// does not exist or is a regular file.
TEST(AtomicFile, UnwritableDirectoryThrowsAndLeavesNothing) {
  test::TempDir dir;
  const std::string missing = dir.file("missing/out.txt");
  try {
    write_file_atomically(missing, "x");
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()), missing + ": cannot write: No such file or directory");
  }
  write_file_atomically(dir.file("plain"), "x");
  EXPECT_THROW(write_file_atomically(dir.file("plain/out.txt"), "x"), InputError);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"plain"});
}

TEST(AtomicFile, FailedRenameRemovesTheTemporary) {
  test::TempDir dir;
  std::filesystem::create_directory(dir.file("taken"));
  std::filesystem::create_directory(dir.file("taken/inside"));
  // rename(2) cannot replace a non-empty directory with a file.
  try {
    write_file_atomically(dir.file("taken"), "x");
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()).rfind(dir.file("taken") + ": cannot replace: ", 0), 0u)
        << error.what();
  }
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"taken"});
}

TEST(AtomicFile, DirectoryPathIsNotAFileName) {
  test::TempDir dir;
  EXPECT_THROW(AtomicFile(dir.file("") + "/"), InputError);
  EXPECT_TRUE(dir.entries().empty());
}

}  // namespace
}  // namespace rbpart
