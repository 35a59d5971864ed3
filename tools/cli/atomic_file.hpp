// Writing an output file all at once or not at all.
//
// AtomicFile::open() creates a temporary file beside the target (same
// directory, so the final rename stays within one file system; name
// ".<target>.tmp-<pid>-<n>", created with O_EXCL so it never clobbers
// anything). commit() writes the contents, flushes them to disk, closes the
// file and renames it over the target, which POSIX makes atomic: readers see
// either the old file or the complete new one. If anything fails, or the
// object is destroyed without commit(), the temporary file is removed, so a
// failure leaves the target as it was and nothing half-written beside it.
//
// Opening early (before a long computation) makes an unwritable path fail
// fast. The new file gets the target's permission bits if it already
// exists, otherwise 0666 less the umask, as a plain open() would.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace hedra::tool {

class AtomicFile {
 public:
  // Creates the temporary file for `target`; on failure returns nothing and
  // sets `error` to "target: reason".
  static std::optional<AtomicFile> open(const std::string& target, std::string& error);

  AtomicFile(AtomicFile&& other) noexcept;
  AtomicFile& operator=(AtomicFile&& other) noexcept;  // discards this one's temporary first
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile();

  // Writes `contents` and replaces the target; false with `error` set
  // ("target: reason") on failure, after which the target is untouched.
  // Call at most once.
  bool commit(std::string_view contents, std::string& error);

  const std::string& target() const { return target_; }

 private:
  AtomicFile(std::string target, std::string temporary, int fd);
  void discard();

  std::string target_;
  std::string temporary_;
  int fd_ = -1;
};

}  // namespace hedra::tool
