#pragma once

// wheeltec-record's service: the daemon's telemetry, status and events (a Subscription
// that reconnects with backoff) into the black box, files in --dir, a tick four times a
// second. One thread.

#include <memory>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>

#include "wheeltec/client/subscription.hpp"

#include "black_box.hpp"
#include "directory_store.hpp"
#include "recorder_config.hpp"

namespace wheeltec::record {

class Recorder {
 public:
  Recorder(boost::asio::io_context& io, RecorderConfig config);

  void start();
  // Finishes the files being written with what they hold.
  void stop();

 private:
  void schedule_tick();

  RecorderConfig config_;
  DirectoryStore store_;
  BlackBox black_box_;
  client::Subscription subscription_;
  boost::asio::steady_timer tick_timer_;
  bool stopped_ = false;
};

}  // namespace wheeltec::record
