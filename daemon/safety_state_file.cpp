#include "safety_state_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "wheeltec/config.hpp"

namespace wheeltec::daemon {
namespace {

constexpr const char* kKey = "safety.state_file";

std::string directory_of(const std::string& path) {
  const auto slash = path.rfind('/');
  return slash == 0 ? std::string("/") : path.substr(0, slash);
}

std::string temporary_of(const std::string& path) { return path + ".tmp"; }

std::string errno_text(int error) { return std::error_code(error, std::generic_category()).message(); }

// Writes all of `text` to a new file at `path` and fsyncs it; errno's text on failure.
std::optional<std::string> write_synced(const std::string& path, const std::string& text) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return errno_text(errno);
  std::size_t written = 0;
  while (written < text.size()) {
    const ssize_t n = ::write(fd, text.data() + written, text.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int error = errno;
      ::close(fd);
      return errno_text(error);
    }
    written += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) {
    const int error = errno;
    ::close(fd);
    return errno_text(error);
  }
  if (::close(fd) != 0) return errno_text(errno);
  return std::nullopt;
}

// The whole file (a state file is a few hundred bytes: more is not one); errno on failure.
std::optional<int> read_file(const std::string& path, std::string& text) {
  constexpr std::size_t kMaxBytes = 64 * 1024;
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return errno;
  char buffer[4096];
  while (text.size() <= kMaxBytes) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int error = errno;
      ::close(fd);
      return error;
    }
    if (n == 0) break;
    text.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(fd);
  return std::nullopt;
}

void sync_directory(const std::string& directory) {
  const int fd = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

}  // namespace

SafetyState SafetyStateFile::load(RealtimeNanos now) const {
  if (!path_) return std::nullopt;
  std::string text;
  if (const auto problem = read_file(*path_, text)) {
    if (*problem == ENOENT) return std::nullopt;
    spdlog::error("{} {}: cannot be read ({}): starting latched", kKey, *path_, errno_text(*problem));
    return damaged_file_latch(errno_text(*problem), now);
  }
  auto decoded = decode_safety_file(text);
  if (const auto* problem = std::get_if<std::string>(&decoded)) {
    spdlog::error("{} {}: not a state file of wheeltecd ({}): starting latched", kKey, *path_, *problem);
    return damaged_file_latch(*problem, now);
  }
  SafetyState state = std::get<SafetyState>(std::move(decoded));
  if (state) {
    spdlog::warn("emergency stop latched since before this start ({}{}{}): release it to drive",
                 to_string(state->source), state->reason.empty() ? "" : ": ", state->reason);
  }
  return state;
}

bool SafetyStateFile::save(const SafetyState& state) {
  if (!path_) return true;
  const std::string temporary = temporary_of(*path_);
  if (const auto problem = write_synced(temporary, encode_safety_file(state))) {
    spdlog::error("{} {}: cannot write {} ({}); the latch holds until this daemon stops", kKey, *path_, temporary,
                  *problem);
    ::unlink(temporary.c_str());
    return false;
  }
  if (::rename(temporary.c_str(), path_->c_str()) != 0) {
    spdlog::error("{} {}: cannot rename {} over it ({}); the latch holds until this daemon stops", kKey, *path_,
                  temporary, errno_text(errno));
    ::unlink(temporary.c_str());
    return false;
  }
  sync_directory(directory_of(*path_));
  return true;
}

void SafetyStateFile::check_writable(const std::string& path) {
  const std::string directory = directory_of(path);
  struct stat info {};
  if (::stat(directory.c_str(), &info) != 0) {
    throw ConfigError(kKey, fmt::format("the directory of {} cannot be used: {}", path, errno_text(errno)));
  }
  if (!S_ISDIR(info.st_mode)) throw ConfigError(kKey, fmt::format("{} is not a directory (for {})", directory, path));
  if (::stat(path.c_str(), &info) == 0 && S_ISDIR(info.st_mode)) {
    throw ConfigError(kKey, fmt::format("{} is a directory, not a file", path));
  }
  const std::string temporary = temporary_of(path);
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) throw ConfigError(kKey, fmt::format("cannot write {} beside {}: {}", temporary, path, errno_text(errno)));
  ::close(fd);
  ::unlink(temporary.c_str());
}

}  // namespace wheeltec::daemon
