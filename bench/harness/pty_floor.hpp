#pragma once

#include <cstddef>
#include <vector>

namespace bench {

// The pseudo-terminal's own cost, in one process and no daemon: `to_slave_bytes` written on
// a master to their read on its slave, and `to_master_bytes` back, each direction `count`
// times, in microseconds. The serial benchmark's floor, as the bus floor is vcan's.
struct PtyFloor {
  std::vector<double> to_slave, to_master;
};
PtyFloor pty_floor(int count, std::size_t to_slave_bytes, std::size_t to_master_bytes);

}  // namespace bench
