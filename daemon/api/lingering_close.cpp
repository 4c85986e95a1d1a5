#include "lingering_close.hpp"

#include <array>
#include <memory>
#include <utility>

#include <boost/asio/buffer.hpp>
#include <boost/asio/steady_timer.hpp>

namespace wheeltec::daemon {
namespace {

using Socket = boost::asio::local::stream_protocol::socket;

class LingeringClose : public std::enable_shared_from_this<LingeringClose> {
 public:
  explicit LingeringClose(Socket socket) : socket_(std::move(socket)), deadline_(socket_.get_executor()) {}

  void start() {
    boost::system::error_code ignored;
    socket_.shutdown(Socket::shutdown_send, ignored);
    deadline_.expires_after(kLingerTimeout);
    deadline_.async_wait([self = shared_from_this()](const boost::system::error_code& error) {
      if (!error) self->close();
    });
    discard_input();
  }

 private:
  void discard_input() {
    if (discarded_ > kLingerMaxBytes) {
      close();
      return;
    }
    socket_.async_read_some(boost::asio::buffer(chunk_), [self = shared_from_this()](
                                                             const boost::system::error_code& error, std::size_t bytes) {
      if (error) {
        self->close();
        return;
      }
      self->discarded_ += bytes;
      self->discard_input();
    });
  }

  void close() {
    boost::system::error_code ignored;
    socket_.close(ignored);
    deadline_.cancel();
  }

  Socket socket_;
  boost::asio::steady_timer deadline_;
  std::array<char, 16 * 1024> chunk_{};
  std::size_t discarded_ = 0;
};

}  // namespace

void close_lingering(Socket socket) { std::make_shared<LingeringClose>(std::move(socket))->start(); }

}  // namespace wheeltec::daemon
