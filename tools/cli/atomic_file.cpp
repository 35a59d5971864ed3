// AtomicFile: temporary file beside the target, then fsync and rename; see
// atomic_file.hpp. Invariant: while fd_ >= 0 or temporary_ is non-empty, the
// temporary file exists and belongs to this object, and every path out of
// commit() or the destructor either renamed it onto the target or removed it.
#include "cli/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>
#include <utility>

namespace hedra::tool {

namespace {

std::string failure(const std::string& target, const char* action, int error) {
  return target + ": " + action + ": " + std::strerror(error);
}

}  // namespace

std::optional<AtomicFile> AtomicFile::open(const std::string& target, std::string& error) {
  const std::filesystem::path path(target);
  if (target.empty() || !path.has_filename()) {
    error = "'" + target + "': not a file name";
    return std::nullopt;
  }
  struct stat existing {};
  const bool exists = ::stat(target.c_str(), &existing) == 0;
  if (exists && S_ISDIR(existing.st_mode)) {
    error = target + ": cannot write: is a directory";
    return std::nullopt;
  }
  const std::filesystem::path directory = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  const std::string stem = "." + path.filename().string() + ".tmp-" + std::to_string(::getpid()) + "-";
  for (int attempt = 0; attempt < 100; ++attempt) {
    const std::string temporary = (directory / (stem + std::to_string(attempt))).string();
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) {
      if (errno == EEXIST) continue;  // a leftover of an earlier run with the same pid
      error = failure(target, "cannot write", errno);
      return std::nullopt;
    }
    if (exists && S_ISREG(existing.st_mode)) {
      // Keep the permissions of the file being replaced; failing to is not
      // worth refusing the write.
      (void)::fchmod(fd, existing.st_mode & 07777);
    }
    return AtomicFile(target, temporary, fd);
  }
  error = target + ": cannot write: too many leftover temporary files named " + stem + "*";
  return std::nullopt;
}

AtomicFile::AtomicFile(std::string target, std::string temporary, int fd)
    : target_(std::move(target)), temporary_(std::move(temporary)), fd_(fd) {}

AtomicFile::AtomicFile(AtomicFile&& other) noexcept
    : target_(std::move(other.target_)),
      temporary_(std::exchange(other.temporary_, std::string())),
      fd_(std::exchange(other.fd_, -1)) {}

AtomicFile& AtomicFile::operator=(AtomicFile&& other) noexcept {
  if (this != &other) {
    discard();
    target_ = std::move(other.target_);
    temporary_ = std::exchange(other.temporary_, std::string());
    fd_ = std::exchange(other.fd_, -1);
  }
  return *this;
}

AtomicFile::~AtomicFile() { discard(); }

void AtomicFile::discard() {
  if (fd_ >= 0) {
    ::close(fd_);
    fd_ = -1;
  }
  if (!temporary_.empty()) {
    ::unlink(temporary_.c_str());
    temporary_.clear();
  }
}

bool AtomicFile::commit(std::string_view contents, std::string& error) {
  if (fd_ < 0) {
    error = target_ + ": internal error: file already committed or discarded";
    return false;
  }
  const char* data = contents.data();
  std::size_t left = contents.size();
  while (left > 0) {
    const ssize_t written = ::write(fd_, data, left);
    if (written < 0) {
      if (errno == EINTR) continue;
      error = failure(target_, "cannot write", errno);
      discard();
      return false;
    }
    data += written;
    left -= static_cast<std::size_t>(written);
  }
  // Without fsync a crash after the rename could leave an empty target.
  if (::fsync(fd_) != 0) {
    error = failure(target_, "cannot write (fsync)", errno);
    discard();
    return false;
  }
  const int fd = std::exchange(fd_, -1);
  if (::close(fd) != 0) {
    error = failure(target_, "cannot write (close)", errno);
    discard();
    return false;
  }
  if (::rename(temporary_.c_str(), target_.c_str()) != 0) {
    error = failure(target_, "cannot replace", errno);
    discard();
    return false;
  }
  temporary_.clear();
  return true;
}

}  // namespace hedra::tool
