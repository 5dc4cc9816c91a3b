#include "io/atomic_file.hpp"

#include "core/error.hpp"

#include <atomic>
#include <cerrno>
#include <stdexcept>
#include <system_error>

#include <fcntl.h>
#include <unistd.h>

namespace rbpart {

namespace {

// Distinguishes temporary files of concurrent writers within one process; the pid separates
// processes, and O_EXCL settles any remaining collision.
std::atomic<unsigned> temp_counter{0};

std::string error_text(int err) { return std::generic_category().message(err); }

}  // namespace

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  const auto slash = path_.find_last_of('/');
  const std::string dir = slash == std::string::npos ? std::string() : path_.substr(0, slash + 1);
  const std::string base = slash == std::string::npos ? path_ : path_.substr(slash + 1);
  if (base.empty()) throw InputError(path_ + ": not a file name");
  // Hidden name in the target's own directory: rename(2) is atomic only within one file system.
  for (;;) {
    temp_path_ = dir + "." + base + ".tmp-" + std::to_string(::getpid()) + "-" +
                 std::to_string(temp_counter.fetch_add(1));
    // 0666 so that the umask, not this writer, decides the final file's permissions.
    const int fd = ::open(temp_path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      file_ = ::fdopen(fd, "w");
      if (!file_) {
        const int err = errno;
        ::close(fd);
        fail("cannot write", err);
      }
      return;
    }
    if (errno != EEXIST) {
      const int err = errno;
      temp_path_.clear();  // nothing was created
      throw InputError(path_ + ": cannot write: " + error_text(err));
    }
  }
}

AtomicFile::~AtomicFile() { discard(); }

void AtomicFile::write(std::string_view text) {
  if (write_failed_ || text.empty()) return;
  if (!file_) throw std::logic_error("AtomicFile::write after commit");
  if (std::fwrite(text.data(), 1, text.size(), file_) != text.size()) {
    write_failed_ = true;
    write_errno_ = errno;
  }
}

void AtomicFile::commit() {
  if (!file_) throw std::logic_error("AtomicFile::commit called twice");
  if (!write_failed_ && std::fflush(file_) != 0) {
    write_failed_ = true;
    write_errno_ = errno;
  }
  // The data must be on disk before the rename, or a crash could leave a renamed but empty file.
  if (!write_failed_ && ::fsync(::fileno(file_)) != 0) {
    write_failed_ = true;
    write_errno_ = errno;
  }
  std::FILE* file = file_;
  file_ = nullptr;
  if (std::fclose(file) != 0 && !write_failed_) {
    write_failed_ = true;
    write_errno_ = errno;
  }
  if (write_failed_) fail("cannot write", write_errno_);
  if (std::rename(temp_path_.c_str(), path_.c_str()) != 0) fail("cannot replace", errno);
  temp_path_.clear();
}

void AtomicFile::fail(const std::string& what, int err) {
  discard();
  throw InputError(path_ + ": " + what + ": " + error_text(err));
}

void AtomicFile::discard() {
  if (file_) {
    std::fclose(file_);
    file_ = nullptr;
  }
  if (!temp_path_.empty()) {
    ::unlink(temp_path_.c_str());
    temp_path_.clear();
  }
}

void write_file_atomically(const std::string& path, std::string_view content) {
  AtomicFile file(path);
  file.write(content);
  file.commit();
}

}  // namespace rbpart
