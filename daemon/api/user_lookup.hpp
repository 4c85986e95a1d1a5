#pragma once

#include <sys/types.h>

#include <optional>
#include <string>

namespace wheeltec::daemon {

// Resolves a user given as a name or a decimal uid (no range check against the passwd
// database for numbers: a uid need not have an entry). Empty when the name is unknown.
std::optional<uid_t> lookup_user(const std::string& name_or_uid);

// The same for groups.
std::optional<gid_t> lookup_group(const std::string& name_or_gid);

}  // namespace wheeltec::daemon
