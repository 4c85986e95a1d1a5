#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>

#include "emulated_controller.hpp"
#include "emulator_options.hpp"
#include "serial_command_reader.hpp"
#include "serial_line.hpp"
#include "serial_record_writer.hpp"

namespace wheeltec::emulator {

// The emulated controller on its serial line (--serial): the line, what reads commands
// off it and what writes records on it, and the unplug and replug the options ask for.
class SerialChassis {
 public:
  SerialChassis(boost::asio::io_context& io, const EmulatorOptions& options, const SerialLineOptions& line,
                std::uint32_t seed);

  // Publishes the line and starts; returns a one-line reason on failure.
  std::optional<std::string> start();

 private:
  void unplug();
  void replug();

  SerialLineOptions line_options_;
  SerialCommandReader commands_;
  SerialLine line_;
  SerialRecordWriter records_;
  boost::asio::steady_timer plug_timer_;
  EmulatedController controller_;
};

}  // namespace wheeltec::emulator
