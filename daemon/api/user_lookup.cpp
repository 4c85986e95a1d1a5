#include "user_lookup.hpp"

#include <grp.h>
#include <pwd.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <vector>

namespace wheeltec::daemon {
namespace {

template <typename Id>
std::optional<Id> parse_decimal_id(const std::string& text) {
  unsigned long value = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (text.empty() || ec != std::errc() || ptr != end) return std::nullopt;
  const auto id = static_cast<Id>(value);
  if (static_cast<unsigned long>(id) != value || id == static_cast<Id>(-1)) return std::nullopt;
  return id;
}

std::size_t initial_buffer_size(int sysconf_name) {
  const long size = ::sysconf(sysconf_name);
  return size > 0 ? static_cast<std::size_t>(size) : 4096;
}

}  // namespace

std::optional<uid_t> lookup_user(const std::string& name_or_uid) {
  if (auto uid = parse_decimal_id<uid_t>(name_or_uid)) return uid;
  std::vector<char> buffer(initial_buffer_size(_SC_GETPW_R_SIZE_MAX));
  for (;;) {
    passwd entry{};
    passwd* found = nullptr;
    const int error = ::getpwnam_r(name_or_uid.c_str(), &entry, buffer.data(), buffer.size(), &found);
    if (error == ERANGE && buffer.size() < (1u << 20)) {
      buffer.resize(buffer.size() * 2);
      continue;
    }
    if (error != 0 || found == nullptr) return std::nullopt;
    return found->pw_uid;
  }
}

std::optional<gid_t> lookup_group(const std::string& name_or_gid) {
  if (auto gid = parse_decimal_id<gid_t>(name_or_gid)) return gid;
  std::vector<char> buffer(initial_buffer_size(_SC_GETGR_R_SIZE_MAX));
  for (;;) {
    group entry{};
    group* found = nullptr;
    const int error = ::getgrnam_r(name_or_gid.c_str(), &entry, buffer.data(), buffer.size(), &found);
    if (error == ERANGE && buffer.size() < (1u << 20)) {
      buffer.resize(buffer.size() * 2);
      continue;
    }
    if (error != 0 || found == nullptr) return std::nullopt;
    return found->gr_gid;
  }
}

}  // namespace wheeltec::daemon
