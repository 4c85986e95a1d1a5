#include "record_directory.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <fmt/format.h>

namespace wheeltec::web {
namespace {

std::string failure(const std::string& what, int error) { return fmt::format("{}: {}", what, std::strerror(error)); }

}  // namespace

DirectoryListing list_directory(const std::string& directory) {
  DirectoryListing listing;
  const int fd = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) {
    if (errno != ENOENT) listing.error = failure("cannot read " + directory, errno);
    return listing;
  }
  DIR* dir = ::fdopendir(fd);
  if (dir == nullptr) {
    listing.error = failure("cannot read " + directory, errno);
    ::close(fd);
    return listing;
  }
  while (const dirent* entry = ::readdir(dir)) {
    // Only names that could be recordings are looked at: a directory full of other files
    // costs no lstat() each.
    if (!record_of_name(entry->d_name)) continue;
    struct stat about {};
    if (::fstatat(::dirfd(dir), entry->d_name, &about, AT_SYMLINK_NOFOLLOW) != 0) continue;  // gone meanwhile
    listing.entries.push_back({entry->d_name, S_ISREG(about.st_mode), static_cast<std::uint64_t>(about.st_size)});
  }
  ::closedir(dir);
  return listing;
}

OpenedRecord open_recording(const std::string& directory, std::string_view name) {
  OpenedRecord opened;
  const std::string path = directory + "/" + std::string(name);
  // O_NOFOLLOW: a symlink is refused (ELOOP) rather than followed out of the directory;
  // O_NONBLOCK: a FIFO under a recording's name cannot hold the server in open().
  const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) {
    if (errno == ENOENT || errno == ELOOP || errno == ENOTDIR) {
      opened.missing = true;
    } else {
      opened.error = failure("cannot open " + path, errno);
    }
    return opened;
  }
  struct stat about {};
  if (::fstat(fd, &about) != 0 || !S_ISREG(about.st_mode)) {
    opened.missing = true;
    ::close(fd);
    return opened;
  }
  opened.fd = fd;
  return opened;
}

ReadRecord read_recording(const std::string& directory, std::string_view name, std::uint64_t max_bytes) {
  ReadRecord read;
  const OpenedRecord opened = open_recording(directory, name);
  if (opened.fd < 0) {
    read.missing = opened.missing;
    read.error = opened.error;
    return read;
  }
  struct stat about {};
  if (::fstat(opened.fd, &about) != 0) {
    read.error = failure("cannot read " + directory + "/" + std::string(name), errno);
  } else if (static_cast<std::uint64_t>(about.st_size) > max_bytes) {
    read.too_large = true;
  } else {
    // Read up to one byte past the size fstat gave: a file that grew meanwhile is too large too.
    read.bytes.resize(static_cast<std::size_t>(about.st_size) + 1);
    std::size_t have = 0;
    while (have < read.bytes.size()) {
      const ssize_t got = ::read(opened.fd, read.bytes.data() + have, read.bytes.size() - have);
      if (got < 0 && errno == EINTR) continue;
      if (got < 0) {
        read.error = failure("cannot read " + directory + "/" + std::string(name), errno);
        break;
      }
      if (got == 0) break;
      have += static_cast<std::size_t>(got);
    }
    if (have > max_bytes) read.too_large = true;
    read.bytes.resize(have > max_bytes ? 0 : have);
  }
  ::close(opened.fd);
  return read;
}

}  // namespace wheeltec::web
