#pragma once

// What wheeltec-record does with what the daemon's socket brings (spec section 10): every
// message goes into the open chunk; a finished chunk (about a second of messages) goes to
// the ring of the last `before` seconds, to the incident file while one is being written,
// and to the continuous file. Times come from the caller and files go to a FileStore, so
// that it runs in the tests as in the program.

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "wheeltec/mcap/chunk.hpp"
#include "wheeltec/mcap/chunk_builder.hpp"
#include "wheeltec/mcap/registry.hpp"

#include "channels.hpp"
#include "file_store.hpp"
#include "incident_window.hpp"
#include "record_ring.hpp"
#include "trigger_detector.hpp"

namespace wheeltec::record {

struct BlackBoxSettings {
  std::chrono::nanoseconds before = std::chrono::seconds(60);
  std::chrono::nanoseconds after = std::chrono::seconds(10);
  TriggerSet triggers = default_triggers();
  std::uint64_t max_bytes = std::uint64_t{1} << 30;
  std::optional<std::chrono::nanoseconds> continuous_split;  // none: no continuous files
  std::string library = "wheeltec-record";                   // the files' Header
  // A chunk is finished once it spans this long or holds this much.
  std::chrono::nanoseconds chunk_span = std::chrono::seconds(1);
  std::uint64_t chunk_bytes = 256 * 1024;
};

// The registry of the five channels (channels()), the same in every chunk and file.
mcap::Registry recording_registry();

class BlackBox {
 public:
  // Applies the retention rule to what `files` holds already.
  BlackBox(BlackBoxSettings settings, FileStore& files);
  ~BlackBox();
  BlackBox(const BlackBox&) = delete;
  BlackBox& operator=(const BlackBox&) = delete;

  // A notification's object, as the daemon sent it; `received`: when it came.
  void on_telemetry(const Json& record, RealtimeNanos received);
  void on_status(const Json& status, RealtimeNanos received);
  void on_event(const Json& event, RealtimeNanos received);
  // The subscription that was up is lost.
  void on_daemon_lost(RealtimeNanos now);
  // Called often (a few times a second): finishes chunks and files whose time has come.
  void on_tick(RealtimeNanos now);
  // At exit: the files being written are finished with what they hold.
  void finish(RealtimeNanos now);

  std::size_t ring_bytes() const { return ring_.bytes(); }
  std::size_t ring_chunks() const { return ring_.size(); }
  std::uint64_t files_written() const { return files_written_; }

 private:
  struct StatusAt {
    Json status;
    RealtimeNanos received;
  };
  struct RingChunk {
    mcap::Chunk chunk;
    std::optional<StatusAt> status_before;  // the latest status before its first message
  };
  class OpenFile;

  void add(Channel channel, RealtimeNanos time, const std::string& payload);
  void cut_chunk_if_due(RealtimeNanos time);
  void cut_chunk();
  void deliver(RingChunk chunk);
  void on_trigger(const FiredTrigger& fired);
  void start_incident(const FiredTrigger& first);
  void finish_incident(const std::vector<FiredTrigger>& triggers);
  void finish_continuous();
  std::unique_ptr<OpenFile> open_file(const std::string& name, const std::optional<StatusAt>& status_before);
  void close_file(std::unique_ptr<OpenFile> file, const std::vector<FiredTrigger>& triggers);
  void apply_retention();

  BlackBoxSettings settings_;
  FileStore& files_;
  mcap::ChunkBuilder builder_;
  std::optional<RealtimeNanos> chunk_first_time_;  // of the open chunk's first message
  std::optional<StatusAt> chunk_status_before_;
  std::optional<StatusAt> latest_status_;
  RecordRing<RingChunk> ring_;
  TriggerDetector detector_;
  IncidentWindow window_;
  std::unique_ptr<OpenFile> incident_;
  std::unique_ptr<OpenFile> continuous_;
  std::uint64_t files_written_ = 0;
  std::optional<std::string> last_finished_;  // the file committed last, kept by retention
  std::string reported_over_limit_;           // logged once, not at every retention pass
};

}  // namespace wheeltec::record
