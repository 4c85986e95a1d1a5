#include "serial_record_writer.hpp"

#include "emulated_controller.hpp"
#include "wheeltec/frames/serial_frame.hpp"

namespace wheeltec::emulator {

SerialRecordWriter::SerialRecordWriter(const serial::SerialFaultRates& faults, bool docked, std::uint32_t seed,
                                       SerialLine& line)
    : faults_(faults, seed), docked_(docked), line_(line) {}

void SerialRecordWriter::write(const RecordBytes& record) {
  outgoing_.clear();
  faults_.apply(record, outgoing_);
  if (docked_) {
    const serial::ChargeFrame charge = serial::encode_charge_frame(kDockedState);
    outgoing_.insert(outgoing_.end(), charge.begin(), charge.end());
  }
  line_.write(outgoing_);
}

}  // namespace wheeltec::emulator
