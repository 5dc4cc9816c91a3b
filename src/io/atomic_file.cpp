#include "io/atomic_file.hpp"

#include "core/error.hpp"
#include "core/interrupt.hpp"

#include <atomic>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cstring>
#include <stdexcept>
#include <system_error>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace rbpart {

namespace {

// Distinguishes temporary files of concurrent writers within one process; the pid separates
// processes, and O_EXCL settles any remaining collision.
std::atomic<unsigned> temp_counter{0};

std::string error_text(int err) { return std::generic_category().message(err); }

// The descriptor that "-", /dev/stdout, /dev/stderr, /dev/fd/N or /proc/self/fd/N names, else -1.
// Opening such a path anew would give a second file offset, starting at 0, on whatever the
// descriptor is: a log that the shell appends to would be overwritten from its start.
int named_descriptor(const std::string& path) {
  if (path == "-" || path == "/dev/stdout") return 1;
  if (path == "/dev/stderr") return 2;
  for (const char* prefix : {"/dev/fd/", "/proc/self/fd/"}) {
    const std::size_t n = std::strlen(prefix);
    if (path.size() == n || path.size() > n + 9 || path.compare(0, n, prefix) != 0) continue;
    int fd = 0;
    for (std::size_t i = n; i < path.size(); ++i) {
      if (!std::isdigit(static_cast<unsigned char>(path[i]))) return -1;
      fd = 10 * fd + (path[i] - '0');
    }
    return fd;
  }
  return -1;
}

// The name at the end of a chain of symlinks (relative targets read from their link's directory):
// where the file is, or is to be created for a dangling link.
std::string final_link_name(const std::string& path) {
  std::string name = path;
  for (int hop = 0; hop < 40; ++hop) {
    struct stat st;
    if (::lstat(name.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return name;
    std::string target(PATH_MAX, '\0');
    const ssize_t length = ::readlink(name.c_str(), target.data(), target.size());
    if (length <= 0) return name;
    target.resize(static_cast<std::size_t>(length));
    const auto slash = name.find_last_of('/');
    name = target[0] == '/' || slash == std::string::npos ? target : name.substr(0, slash + 1) + target;
  }
  throw InputError(path + ": too many levels of symbolic links");
}

}  // namespace

OutputTarget classify_output(const std::string& path) {
  if (path.empty()) throw InputError("an output path is empty");
  OutputTarget target;
  target.path = path;
  target.fd = named_descriptor(path);
  if (target.fd >= 0) {
    if (::fcntl(target.fd, F_GETFD) < 0) throw InputError(path + ": descriptor " + std::to_string(target.fd) + " is not open");
    target.kind = OutputTarget::Descriptor;
    return target;
  }
  struct stat st;
  // Nothing there (yet), or a path whose temporary file's creation will name the problem.
  if (::stat(path.c_str(), &st) != 0) {
    target.path = final_link_name(path);
    return target;
  }
  if (S_ISDIR(st.st_mode)) throw InputError(path + ": is a directory");
  if (!S_ISREG(st.st_mode)) {
    target.kind = OutputTarget::WriteThrough;
    return target;
  }
  target.path = final_link_name(path);
  return target;
}

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)), target_(classify_output(path_)) {
  if (target_.kind != OutputTarget::Replace) {
    // A FIFO's open waits for its reader, as any writer's does.
    const int fd = target_.kind == OutputTarget::Descriptor ? ::fcntl(target_.fd, F_DUPFD_CLOEXEC, 3)
                                                             : ::open(path_.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0) throw InputError(path_ + ": cannot write: " + error_text(errno));
    attach(fd);
    return;
  }
  const std::string& target = target_.path;
  const auto slash = target.find_last_of('/');
  const std::string dir = slash == std::string::npos ? std::string() : target.substr(0, slash + 1);
  const std::string base = slash == std::string::npos ? target : target.substr(slash + 1);
  if (base.empty()) throw InputError(path_ + ": not a file name");
  // Hidden name in the target's own directory: rename(2) is atomic only within one file system.
  for (;;) {
    temp_path_ = dir + "." + base + ".tmp-" + std::to_string(::getpid()) + "-" +
                 std::to_string(temp_counter.fetch_add(1));
    // Registered before it exists: a signal between open and registration would leave it behind.
    temp_slot_ = register_temp_file(temp_path_.c_str());
    // 0666 so that the umask, not this writer, decides the final file's permissions.
    const int fd = ::open(temp_path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      attach(fd);
      return;
    }
    const int err = errno;
    unregister_temp_file(temp_slot_);
    temp_slot_ = -1;
    if (err != EEXIST) {
      temp_path_.clear();  // nothing was created
      throw InputError(path_ + ": cannot write: " + error_text(err));
    }
  }
}

AtomicFile::~AtomicFile() { discard(); }

void AtomicFile::attach(int fd) {
  file_ = ::fdopen(fd, "w");
  if (!file_) {
    const int err = errno;
    ::close(fd);
    fail("cannot write", err);
  }
}

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
  const bool replace = target_.kind == OutputTarget::Replace;
  if (!write_failed_ && std::fflush(file_) != 0) {
    write_failed_ = true;
    write_errno_ = errno;
  }
  // The data must be on disk before the rename, or a crash could leave a renamed but empty file.
  // (A pipe or terminal cannot be synced, and there is no rename to order it before.)
  if (replace && !write_failed_ && ::fsync(::fileno(file_)) != 0) {
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
  if (replace && std::rename(temp_path_.c_str(), target_.path.c_str()) != 0) fail("cannot replace", errno);
  unregister_temp_file(temp_slot_);
  temp_slot_ = -1;
  temp_path_.clear();
}

void AtomicFile::fail(const std::string& what, int err) {
  discard();
  throw InputError(path_ + ": " + what + ": " + error_text(err));
}

// A written-through output keeps what was flushed already: it cannot be taken back.
void AtomicFile::discard() {
  if (file_) {
    std::fclose(file_);
    file_ = nullptr;
  }
  if (!temp_path_.empty()) {
    unregister_temp_file(temp_slot_);
    temp_slot_ = -1;
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
