#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "pseudo_terminal.hpp"

namespace bench {

// The benchmark as the chassis' controller on a serial line: the master of a pseudo-terminal
// whose slave is set raw before it is published at `link` (a symlink, by rename, as udev
// does; emulator/pseudo_terminal). It writes what the controller sends and finds the
// 11-byte command frames in what the daemon writes. It keeps a descriptor of the slave
// open itself (never read), so that the master sees no hang-up while the daemon has not
// opened the port yet.
class PtyEndpoint {
 public:
  explicit PtyEndpoint(const std::filesystem::path& link);
  PtyEndpoint(PtyEndpoint&&) = delete;  // owns the descriptors and the link: neither copied nor moved
  ~PtyEndpoint();

  // All of `bytes`, in one write() when the pty takes them; waits for room otherwise.
  void write(std::span<const std::uint8_t> bytes);
  // The next well-formed command frame whose X is `x_mm_s` (others are skipped), read within
  // timeout_ms; the time it was read (now_us()'s clock; a pty has no receive timestamp).
  std::optional<double> await_command(int x_mm_s, int timeout_ms);
  // Discards what the daemon has written so far.
  void drain();
  const std::string& slave_path() const { return slave_path_; }

 private:
  bool fill(int timeout_ms);

  std::filesystem::path link_;
  std::string slave_path_;
  int master_ = -1;
  int slave_keeper_ = -1;
  std::vector<std::uint8_t> pending_;  // read from the master, not yet parsed
};

// Shared with pty_floor: a new raw pseudo-terminal (throws when none can be had), and all of
// `bytes` written to a non-blocking descriptor, waiting for room.
wheeltec::emulator::PseudoTerminal open_pty();
void write_all(int fd, std::span<const std::uint8_t> bytes);

}  // namespace bench
