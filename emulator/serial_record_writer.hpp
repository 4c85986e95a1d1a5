#pragma once

#include <cstdint>
#include <vector>

#include "serial_line.hpp"
#include "wheeltec/emulator/serial_fault_injector.hpp"
#include "wheeltec/frames/telemetry_record.hpp"

namespace wheeltec::emulator {

// Writes the controller's records on the serial line, each whole in one write, with the
// serial faults and, while docked, a charge frame after each.
class SerialRecordWriter {
 public:
  SerialRecordWriter(const serial::SerialFaultRates& faults, bool docked, std::uint32_t seed, SerialLine& line);

  void write(const RecordBytes& record);
  bool docked() const { return docked_; }

 private:
  serial::SerialFaultInjector faults_;
  bool docked_;
  SerialLine& line_;
  std::vector<std::uint8_t> outgoing_;
};

}  // namespace wheeltec::emulator
