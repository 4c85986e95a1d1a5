#pragma once

// Broker loss to the zero frame: while a bridge drives the robot (its velocity in the command
// frames), the broker is killed (SIGKILL) and the time runs from just before kill() to the
// first command frame with zero velocity (CommandFrames: on CAN the kernel's receive
// timestamp of the 0x121 frame; on a serial line when it was read). The other bridges of the
// same daemon are frozen (SIGSTOP) meanwhile, so that only the measured one can stop the
// robot; the broker is restarted on the same port after each kill, and the next round
// starts once the next bridge drives again (it has reconnected).

#include <sys/types.h>

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "command_frames.hpp"
#include "fleet_processes.hpp"

namespace bench {

struct BridgeUnderTest {
  std::string name;         // as printed
  std::string drive_topic;  // PREFIX/ROBOT/cmd/drive of this bridge
  pid_t pid;
};

struct LossSeries {
  std::vector<double> ms;    // kill -> zero frame, one per round
  int missed = 0;            // no zero frame within 2 s
  int never_driving = 0;     // the bridge did not drive within 20 s after the restart
  nlohmann::json to_json() const;
};

// `rounds` kills per bridge, alternating which bridge goes first; the results in the order of `bridges`.
std::vector<LossSeries> measure_broker_loss(Broker& broker, CommandFrames& frames,
                                            const std::vector<BridgeUnderTest>& bridges, int rounds);

}  // namespace bench
