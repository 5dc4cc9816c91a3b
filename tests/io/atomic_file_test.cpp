// Atomic output: a file appears complete or not at all, and never leaves a temporary behind.
#include "io/atomic_file.hpp"

#include "core/error.hpp"
#include "core/interrupt.hpp"
#include "io/temp_dir.hpp"

#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <stdexcept>

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

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
  AtomicFile file(dir.file("taken"));
  file.write("x");
  // A directory appears at the target after the check: rename(2) cannot replace a non-empty
  // directory with a file.
  std::filesystem::create_directory(dir.file("taken"));
  std::filesystem::create_directory(dir.file("taken/inside"));
  try {
    file.commit();
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
  EXPECT_THROW(AtomicFile(dir.file("missing/")), InputError);
  EXPECT_TRUE(dir.entries().empty());
}

// Regular files are replaced; everything else is written where it is (issue #26).
TEST(ClassifyOutput, NamesWhatEachPathIs) {
  test::TempDir dir;
  const std::string file = dir.file("file"), missing = dir.file("missing");
  write_file_atomically(file, "x");
  std::filesystem::create_symlink(file, dir.file("to_file"));
  std::filesystem::create_symlink("file", dir.file("relative"));
  std::filesystem::create_symlink("to_file", dir.file("chain"));
  std::filesystem::create_symlink(missing, dir.file("dangling"));
  std::filesystem::create_directory(dir.file("sub"));
  std::filesystem::create_symlink(dir.file("sub"), dir.file("to_sub"));
  std::filesystem::create_symlink(dir.file("loop"), dir.file("loop"));
  ASSERT_EQ(::mkfifo(dir.file("fifo").c_str(), 0600), 0);
  const auto expect = [](const std::string& path, OutputTarget::Kind kind, const std::string& where) {
    const OutputTarget t = classify_output(path);
    EXPECT_EQ(t.kind, kind) << path;
    if (kind != OutputTarget::Descriptor) EXPECT_EQ(t.path, where) << path;
  };
  expect(file, OutputTarget::Replace, file);
  expect(missing, OutputTarget::Replace, missing);
  expect(dir.file("to_file"), OutputTarget::Replace, file);
  expect(dir.file("relative"), OutputTarget::Replace, file);
  expect(dir.file("chain"), OutputTarget::Replace, file);
  expect(dir.file("dangling"), OutputTarget::Replace, missing);
  expect(dir.file("fifo"), OutputTarget::WriteThrough, dir.file("fifo"));
  expect("/dev/null", OutputTarget::WriteThrough, "/dev/null");
  for (const char* out : {"-", "/dev/stdout", "/dev/fd/1", "/proc/self/fd/1"}) {
    EXPECT_EQ(classify_output(out).kind, OutputTarget::Descriptor) << out;
    EXPECT_EQ(classify_output(out).fd, 1) << out;
  }
  EXPECT_EQ(classify_output("/dev/stderr").fd, 2);
  for (const std::string& refused : {dir.file("sub"), dir.file("to_sub"), dir.file("sub") + "/", dir.file("loop")}) {
    try {
      classify_output(refused);
      ADD_FAILURE() << refused << ": no error";
    } catch (const InputError& error) {
      EXPECT_EQ(std::string(error.what()).rfind(refused + ": ", 0), 0u) << error.what();
    }
  }
  EXPECT_THROW(classify_output("/dev/fd/999999"), InputError);  // not open
}

TEST(AtomicFile, SymlinkIsKeptAndItsTargetReplaced) {
  test::TempDir dir;
  std::filesystem::create_directory(dir.file("data"));
  write_file_atomically(dir.file("data/target"), "old\n");
  std::filesystem::create_symlink("data/target", dir.file("link"));
  write_file_atomically(dir.file("link"), "new\n");
  EXPECT_TRUE(std::filesystem::is_symlink(dir.file("link")));
  EXPECT_EQ(test::read_text(dir.file("data/target")), "new\n");
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"data", "link"}));
  // The temporary file went next to the target, and is gone.
  EXPECT_EQ(test::TempDir::entries_of(dir.file("data")), std::vector<std::string>{"target"});
  // A dangling link: the file is created where it points.
  std::filesystem::create_symlink("data/later", dir.file("ahead"));
  write_file_atomically(dir.file("ahead"), "made\n");
  EXPECT_TRUE(std::filesystem::is_symlink(dir.file("ahead")));
  EXPECT_EQ(test::read_text(dir.file("data/later")), "made\n");
}

TEST(AtomicFile, FifoIsWrittenThroughAndStaysAFifo) {
  test::TempDir dir;
  const std::string fifo = dir.file("fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // A non-blocking read end: the writer need not wait, and a regression cannot hang the test.
  const int in = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
  ASSERT_GE(in, 0);
  write_file_atomically(fifo, "through the pipe\n");
  std::string received(64, '\0');
  const ssize_t n = ::read(in, received.data(), received.size());
  ::close(in);
  received.resize(n > 0 ? n : 0);
  EXPECT_EQ(received, "through the pipe\n");
  EXPECT_TRUE(std::filesystem::is_fifo(fifo));
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"fifo"});
}

TEST(AtomicFile, DirectoryIsRefusedBeforeAnyWrite) {
  test::TempDir dir;
  std::filesystem::create_directory(dir.file("out"));
  try {
    AtomicFile file(dir.file("out"));
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()), dir.file("out") + ": is a directory");
  }
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"out"});
  EXPECT_TRUE(test::TempDir::entries_of(dir.file("out")).empty());
}

// SIGTERM (or Ctrl-C) while an output is open: the temporary file goes, and the process still
// ends by the signal (issue #26: hidden .tmp- files were left behind). In a child process, which
// signals itself once its output's temporary file exists.
TEST(AtomicFile, SignalRemovesTheTemporaryAndStillEndsTheProcess) {
  test::TempDir dir;
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    install_interrupt_handlers();
    AtomicFile file(dir.file("out.txt"));
    file.write("never committed");
    ::kill(::getpid(), SIGTERM);
    ::_exit(3);  // only if the signal did not end the process
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << status;
  EXPECT_TRUE(dir.entries().empty()) << dir.entries().front();
}

}  // namespace
}  // namespace rbpart
