#pragma once

#include <functional>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "wheeltec/control/bus_state.hpp"
#include "wheeltec/frames/charging_dock.hpp"
#include "wheeltec/clocks.hpp"
#include "wheeltec/frames/control_frame.hpp"
#include "wheeltec/control/link_recovery.hpp"
#include "wheeltec/frames/telemetry_record.hpp"
#include "wheeltec/types.hpp"

#include "control/control_ports.hpp"
#include "control/stall_sentinel.hpp"

namespace wheeltec::daemon {

// The daemon's link to the chassis' controller, whatever carries it (CAN or the serial
// line): velocity commands and enable/disable go down in the link's own frames; checked
// telemetry records, the dock's reports and the link's state come up.
class ChassisLink : public CommandSink {
 public:
  struct Handlers {
    std::function<void(const RecordBytes& record, RealtimeNanos time)> record;
    std::function<void(const ChargingDockState& report)> dock;
    std::function<void(BusState state)> state;
    // What the records of one read produced can go out together now.
    std::function<void()> batch_handled;
    // The link's descriptor (the CAN socket, the serial port locked) once open, -1 when it
    // closes; the stall sentinel writes the link's zero frame through it.
    std::function<void(int fd)> port;
  };

  virtual ~ChassisLink() = default;

  // Handlers are called from the io_context.
  virtual void start(Handlers handlers) = 0;
  virtual void stop() = 0;

  virtual BusState state() const = 0;
  // Why it is down: empty while up (and before the first attempt to open it).
  virtual std::optional<LinkDownCause> down_cause() const = 0;
  virtual Transport transport() const = 0;
  virtual const std::string& name() const = 0;  // the interface or the device, as configured
  // The zero command in the link's own frame, as written to its descriptor: for the stall
  // sentinel to write in the daemon's place.
  virtual StallSentinel::ZeroFrame zero_frame() const = 0;
  // Its counters into `stats` (the stats object's link keys).
  virtual void add_stats(nlohmann::json& stats) const = 0;
};

}  // namespace wheeltec::daemon
