#include "pty_floor.hpp"

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>

#include "bench_clock.hpp"
#include "pty_endpoint.hpp"

namespace bench {

namespace {

// Waits for and reads exactly `size` bytes from `fd`.
void read_exactly(int fd, std::size_t size) {
  std::uint8_t buffer[256];
  for (std::size_t got = 0; got < size;) {
    pollfd ready{fd, POLLIN, 0};
    if (::poll(&ready, 1, 1000) <= 0) throw std::runtime_error("pty floor: nothing to read within 1 s");
    const ssize_t n = ::read(fd, buffer, std::min(sizeof(buffer), size - got));
    if (n > 0) got += static_cast<std::size_t>(n);
  }
}

}  // namespace

PtyFloor pty_floor(int count, std::size_t to_slave_bytes, std::size_t to_master_bytes) {
  const auto pty = open_pty();
  const int slave = ::open(pty.slave_path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (slave < 0) throw std::runtime_error("cannot open " + pty.slave_path + ": " + std::strerror(errno));
  const std::vector<std::uint8_t> bytes(std::max(to_slave_bytes, to_master_bytes), 0x55);
  PtyFloor floor;
  for (int i = 0; i < count; ++i) {
    double start = now_us();
    write_all(pty.master_fd, std::span(bytes).first(to_slave_bytes));
    read_exactly(slave, to_slave_bytes);
    floor.to_slave.push_back(now_us() - start);
    start = now_us();
    write_all(slave, std::span(bytes).first(to_master_bytes));
    read_exactly(pty.master_fd, to_master_bytes);
    floor.to_master.push_back(now_us() - start);
  }
  ::close(slave);
  ::close(pty.master_fd);
  return floor;
}

}  // namespace bench
