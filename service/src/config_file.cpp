#include "wheeltec/service/config_file.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "wheeltec/config/config_document.hpp"

namespace wheeltec::service {

std::string read_config_file(const std::string& path, ConfigSecrecy secrecy) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    throw ConfigError(fmt::format("cannot read config file {}: {}", path, std::strerror(errno)));
  }
  if (!S_ISREG(info.st_mode)) throw ConfigError(fmt::format("cannot read config file {}: not a regular file", path));
  if (secrecy == ConfigSecrecy::private_ && (info.st_mode & (S_IROTH | S_IWOTH)) != 0) {
    throw ConfigError(fmt::format("config file {} is readable or writable by others (mode {:04o}); it may hold "
                                  "secrets: chmod o-rw {}",
                                  path, info.st_mode & 07777, path));
  }
  std::ifstream file(path, std::ios::binary);
  if (!file) throw ConfigError(fmt::format("cannot read config file {}: {}", path, std::strerror(errno)));
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad()) throw ConfigError(fmt::format("cannot read config file {}: read error", path));
  return text.str();
}

std::optional<std::string> config_file_to_load(const std::optional<std::string>& explicit_path,
                                               const char* default_path) {
  if (explicit_path) return explicit_path;
  struct stat info {};
  if (::stat(default_path, &info) == 0) return std::string(default_path);
  return std::nullopt;
}

}  // namespace wheeltec::service
