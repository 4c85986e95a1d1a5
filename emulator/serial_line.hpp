#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>

#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/system/error_code.hpp>

namespace wheeltec::emulator {

// The controller's end of its serial line: the master of a pseudo-terminal whose other
// end is published at a path, as udev publishes the USB adapter. Received bytes go to a
// callback. While nobody has the other end open, bytes written are lost, as a USB adapter
// loses them; so are those that do not fit while the reader does not read.
class SerialLine {
 public:
  using BytesHandler = std::function<void(std::span<const std::uint8_t>)>;

  SerialLine(boost::asio::io_context& io, std::filesystem::path link, BytesHandler on_bytes);
  ~SerialLine();  // hangs up; removes the link if it still points at our pseudo-terminal
  SerialLine(const SerialLine&) = delete;
  SerialLine& operator=(const SerialLine&) = delete;

  // A new pseudo-terminal, published at the link; or the reason why not.
  std::optional<std::string> plug();
  // Removes the link and hangs up (the other end reads end of file).
  void unplug();
  bool plugged() const { return master_.is_open(); }
  const std::filesystem::path& link() const { return link_; }

  // In one write().
  void write(std::span<const std::uint8_t> bytes);

 private:
  void read();
  void on_read(const boost::system::error_code& ec, std::size_t size);
  bool other_end_open();
  void note_writable(bool writable, const char* why);

  std::filesystem::path link_;
  BytesHandler on_bytes_;
  boost::asio::posix::stream_descriptor master_;
  boost::asio::steady_timer read_retry_timer_;
  std::string slave_path_;
  std::array<std::uint8_t, 512> read_buffer_{};
  bool writable_ = false;
};

}  // namespace wheeltec::emulator
