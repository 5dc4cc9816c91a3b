#pragma once
// Output files that appear whole or not at all (docs/design.md#contracts: "nothing half written is left
// behind"). Every writer in io/ goes through AtomicFile: the text is written to a temporary file in
// the target's directory (so that the final rename stays on one file system and is atomic), flushed
// to disk, and renamed over the target only by commit(). A file that is never committed — an
// exception, a failed write — is removed by the destructor.
#include <cstdio>
#include <string>
#include <string_view>

namespace rbpart {

class AtomicFile {
 public:
  // Creates the temporary file; throws InputError naming `path` if its directory is not writable.
  explicit AtomicFile(std::string path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  // Buffered; a failure is reported at the latest by commit().
  void write(std::string_view text);
  // Flushes, syncs and renames onto the target. Throws InputError (and removes the temporary file)
  // if any write failed or the rename is refused.
  void commit();

  const std::string& path() const { return path_; }

 private:
  [[noreturn]] void fail(const std::string& what, int err);
  void discard();

  std::string path_;
  std::string temp_path_;
  std::FILE* file_ = nullptr;
  bool write_failed_ = false;
  int write_errno_ = 0;
};

// The whole of `content` as the file `path`, atomically.
void write_file_atomically(const std::string& path, std::string_view content);

}  // namespace rbpart
