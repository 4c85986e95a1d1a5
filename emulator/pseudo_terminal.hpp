#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <variant>

namespace wheeltec::emulator {

// A new pseudo-terminal: the master's file descriptor (non-blocking, close-on-exec; the
// caller owns it) and the path of its slave side.
struct PseudoTerminal {
  int master_fd = -1;
  std::string slave_path;
};

// Opens a pseudo-terminal whose slave side is already raw, 115200 8N1, no echo and no
// flow control, as a USB serial adapter is after the daemon configures it (the slave is
// closed again); or the reason why not.
std::variant<PseudoTerminal, std::string> open_raw_pseudo_terminal();

// Points the symlink `link` at `target` in one step (a temporary symlink beside it,
// renamed over it), as udev re-creates /dev/wheeltec_controller; or the reason why not.
std::optional<std::string> publish_symlink(const std::filesystem::path& link, const std::string& target);

// Removes `link` if it is a symlink to `target`.
void remove_symlink_to(const std::filesystem::path& link, const std::string& target);

}  // namespace wheeltec::emulator
