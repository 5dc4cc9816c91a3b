#pragma once
// Output files that appear whole or not at all (docs/design.md#contracts: "nothing half written is left
// behind"). Every writer in io/ goes through AtomicFile: the text is written to a temporary file in
// the target's directory (so that the final rename stays on one file system and is atomic), flushed
// to disk, and renamed over the target only by commit(). A file that is never committed — an
// exception, a failed write — is removed by the destructor.
//
// Only regular files are replaced so. Standard output ("-", /dev/stdout, /dev/fd/N), FIFOs, devices
// and sockets are written through: renaming over them would put a plain file in place of
// /dev/stdout or /dev/null (issue #26). A symlink is kept and its target written, atomically when
// the target is a regular file. A directory is refused when the AtomicFile is made, before any work.
#include <cstdio>
#include <string>
#include <string_view>

namespace rbpart {

// How an output path is written; classify_output decides it from the file system as it is now.
struct OutputTarget {
  enum Kind {
    Replace,       // a regular file, or none yet: temporary file + rename onto `path`
    WriteThrough,  // FIFO, device, socket: opened and written in place
    Descriptor,    // an already open descriptor `fd` (standard output for "-")
  };
  Kind kind = Replace;
  std::string path;  // Replace: the file to replace, symlinks resolved; WriteThrough: the path given
  int fd = -1;       // Descriptor
};

// Throws InputError naming `path` if it is empty, a directory (or a symlink to one), or a loop of
// symlinks.
OutputTarget classify_output(const std::string& path);

class AtomicFile {
 public:
  // Classifies `path` and opens it (Replace: creates the temporary file); throws InputError naming
  // `path` if it is refused or cannot be opened.
  explicit AtomicFile(std::string path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  // Buffered; a failure is reported at the latest by commit().
  void write(std::string_view text);
  // Flushes, syncs and renames onto the target (written-through outputs: flushes). Throws
  // InputError (and removes the temporary file) if any write failed or the rename is refused.
  void commit();

  const std::string& path() const { return path_; }

 private:
  void attach(int fd);  // buffered writes to `fd`, which it then owns
  [[noreturn]] void fail(const std::string& what, int err);
  void discard();

  std::string path_;
  OutputTarget target_;
  std::string temp_path_;
  int temp_slot_ = -1;  // its registration for removal on SIGINT/SIGTERM (core/interrupt.hpp)
  std::FILE* file_ = nullptr;
  bool write_failed_ = false;
  int write_errno_ = 0;
};

// The whole of `content` as the file `path`, atomically.
void write_file_atomically(const std::string& path, std::string_view content);

}  // namespace rbpart
