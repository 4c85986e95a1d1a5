#include "black_box.hpp"

#include <exception>
#include <utility>

#include <spdlog/spdlog.h>

#include "wheeltec/mcap/writer.hpp"

#include "file_metadata.hpp"
#include "wheeltec/record/file_names.hpp"

namespace wheeltec::record {
namespace {

std::uint16_t channel_id(Channel channel) { return static_cast<std::uint16_t>(static_cast<int>(channel) + 1); }

RealtimeNanos realtime(mcap::Timestamp nanoseconds) {
  return RealtimeNanos(std::chrono::nanoseconds(static_cast<std::int64_t>(nanoseconds)));
}

}  // namespace

mcap::Registry recording_registry() {
  mcap::Registry registry;
  for (const ChannelSpec& spec : channels()) {
    const std::uint16_t schema =
        registry.add_schema(std::string(spec.schema_name), std::string(kSchemaEncoding), mcap::text_bytes(spec.schema));
    registry.add_channel(schema, std::string(spec.topic), std::string(kMessageEncoding));
  }
  return registry;
}

// A file being written: its output, the MCAP writer over it, and the time span it covers.
class BlackBox::OpenFile {
 public:
  OpenFile(std::string name, std::unique_ptr<FileOutput> output, const mcap::Registry& registry,
           const std::string& library)
      : name_(std::move(name)),
        output_(std::move(output)),
        writer_([output = output_.get()](mcap::ByteView bytes) { output->write(bytes); }, registry,
                mcap::WriterOptions{.library = library}) {}

  const std::string& name() const { return name_; }
  mcap::Writer& writer() { return writer_; }
  FileOutput& output() { return *output_; }

  RealtimeNanos start{};  // a continuous file's first message
  RealtimeNanos end{};    // an incident's last time to record

 private:
  std::string name_;
  std::unique_ptr<FileOutput> output_;
  mcap::Writer writer_;
};

BlackBox::BlackBox(BlackBoxSettings settings, FileStore& files)
    : settings_(std::move(settings)),
      files_(files),
      builder_(recording_registry()),
      ring_(settings_.before),
      detector_(settings_.triggers),
      window_(settings_.before, settings_.after) {
  apply_retention();
}

BlackBox::~BlackBox() = default;

void BlackBox::on_telemetry(const Json& record, RealtimeNanos /*received*/) {
  const std::optional<RealtimeNanos> time = time_of_message(record);
  if (!time) return;  // the daemon always sends one; nothing to place without it
  cut_chunk_if_due(*time);  // a record and its /odom and /tf go into one chunk
  add(Channel::telemetry, *time, record.dump());
  if (const auto pose = odom_pose_in_frame(record)) add(Channel::odom, *time, pose->dump());
  if (const auto transform = odom_frame_transform(record)) add(Channel::tf, *time, transform->dump());
}

void BlackBox::on_status(const Json& status, RealtimeNanos received) {
  cut_chunk_if_due(received);
  add(Channel::status, received, status.dump());
  latest_status_ = StatusAt{status, received};
  for (const FiredTrigger& fired : detector_.on_status(status, received)) on_trigger(fired);
}

void BlackBox::on_event(const Json& event, RealtimeNanos received) {
  const RealtimeNanos time = time_of_message(event).value_or(received);
  cut_chunk_if_due(time);
  add(Channel::events, time, event.dump());
  if (const auto fired = detector_.on_event(event, received)) on_trigger(*fired);
}

void BlackBox::on_daemon_lost(RealtimeNanos now) {
  if (const auto fired = detector_.on_daemon_lost(now)) on_trigger(*fired);
  on_tick(now);
}

void BlackBox::on_tick(RealtimeNanos now) {
  if (chunk_first_time_ && now - *chunk_first_time_ >= settings_.chunk_span) cut_chunk();
  if (incident_ && now >= incident_->end) cut_chunk();
  if (const auto ended = window_.on_tick(now)) finish_incident(ended->triggers);
  ring_.drop_expired(now);
}

void BlackBox::finish(RealtimeNanos now) {
  cut_chunk();
  if (const auto* recording = std::get_if<IncidentWindow::Recording>(&window_.state())) {
    finish_incident(recording->triggers);
  }
  finish_continuous();
  ring_.drop_expired(now);
}

void BlackBox::add(Channel channel, RealtimeNanos time, const std::string& payload) {
  if (!chunk_first_time_) {
    chunk_first_time_ = time;
    chunk_status_before_ = latest_status_;
  }
  const std::uint64_t log_time = log_time_ns(time);
  try {
    builder_.add_message(channel_id(channel), log_time, log_time, mcap::text_bytes(payload));
  } catch (const mcap::Error& error) {
    spdlog::warn("{} message not recorded: {}", channel_spec(channel).topic, error.what());
    return;
  }
}

void BlackBox::cut_chunk_if_due(RealtimeNanos time) {
  if (!chunk_first_time_) return;
  if (builder_.uncompressed_size() >= settings_.chunk_bytes || time - *chunk_first_time_ >= settings_.chunk_span) {
    cut_chunk();
  }
}

void BlackBox::cut_chunk() {
  if (builder_.empty()) return;
  RingChunk finished{builder_.finish(), std::move(chunk_status_before_)};
  chunk_first_time_.reset();
  chunk_status_before_.reset();
  deliver(std::move(finished));
}

void BlackBox::deliver(RingChunk chunk) {
  const RealtimeNanos start = realtime(chunk.chunk.message_start_time);
  const RealtimeNanos end = realtime(chunk.chunk.message_end_time);
  if (incident_ && start <= incident_->end) {
    try {
      incident_->writer().write_chunk(chunk.chunk);
    } catch (const std::exception& error) {
      spdlog::error("{}: {}; the incident is not recorded further", incident_->name(), error.what());
      incident_.reset();
    }
  }
  if (settings_.continuous_split) {
    // A file spans at most --split: the chunk that would make it longer starts the next one.
    if (continuous_ && end - continuous_->start > *settings_.continuous_split) finish_continuous();
    if (!continuous_) {
      continuous_ = open_file(file_name(start, Continuous{}), chunk.status_before);
      if (continuous_) continuous_->start = start;
    }
    if (continuous_) {
      try {
        continuous_->writer().write_chunk(chunk.chunk);
      } catch (const std::exception& error) {
        spdlog::error("{}: {}", continuous_->name(), error.what());
        continuous_.reset();
      }
    }
  }
  const std::size_t bytes = chunk.chunk.memory_bytes();
  ring_.push(std::move(chunk), start, end, bytes);
}

void BlackBox::on_trigger(const FiredTrigger& fired) {
  spdlog::info("trigger {}", trigger_name(fired.trigger));
  // A file whose end has passed without a tick takes what came up to now, then ends.
  if (incident_ && fired.time >= incident_->end) cut_chunk();
  const IncidentWindow::TriggerResult result = window_.on_trigger(fired);
  if (result.ended) finish_incident(result.ended->triggers);
  const auto& recording = std::get<IncidentWindow::Recording>(window_.state());
  if (result.change == IncidentWindow::Change::started) {
    start_incident(fired);
  } else if (incident_) {
    incident_->end = recording.end;
  }
}

void BlackBox::start_incident(const FiredTrigger& first) {
  cut_chunk();  // what came up to the trigger is in the ring now
  const auto& recording = std::get<IncidentWindow::Recording>(window_.state());
  std::optional<StatusAt> status_before = latest_status_;
  bool first_chunk = true;
  ring_.for_each_since(recording.start, [&](const auto& entry) {
    if (first_chunk) status_before = entry.item.status_before;
    first_chunk = false;
  });
  incident_ = open_file(file_name(first.time, first.trigger), status_before);
  if (!incident_) return;
  incident_->end = recording.end;
  try {
    ring_.for_each_since(recording.start, [&](const auto& entry) { incident_->writer().write_chunk(entry.item.chunk); });
  } catch (const std::exception& error) {
    spdlog::error("{}: {}; the incident is not recorded", incident_->name(), error.what());
    incident_.reset();
  }
}

void BlackBox::finish_incident(const std::vector<FiredTrigger>& triggers) {
  if (incident_) close_file(std::move(incident_), triggers);
}

void BlackBox::finish_continuous() {
  if (continuous_) close_file(std::move(continuous_), {});
}

std::unique_ptr<BlackBox::OpenFile> BlackBox::open_file(const std::string& name,
                                                        const std::optional<StatusAt>& status_before) {
  try {
    auto file = std::make_unique<OpenFile>(name, files_.create(name), builder_.registry(), settings_.library);
    if (status_before) {
      const std::uint64_t time = log_time_ns(status_before->received);
      file->writer().write_message(channel_id(Channel::status), time, time,
                                   mcap::text_bytes(status_before->status.dump()));
    }
    return file;
  } catch (const std::exception& error) {
    spdlog::error("{}: {}", name, error.what());
    return nullptr;
  }
}

void BlackBox::close_file(std::unique_ptr<OpenFile> file, const std::vector<FiredTrigger>& triggers) {
  try {
    const Json status = latest_status_ ? latest_status_->status : Json();
    file->writer().write_metadata(kMetadataName, file_metadata(status, triggers));
    file->writer().finish();
    file->output().commit();
    ++files_written_;
    last_finished_ = file->name();
    spdlog::info("{} written ({} bytes)", file->name(), file->writer().bytes_written());
  } catch (const std::exception& error) {
    spdlog::error("{}: {}", file->name(), error.what());
  }
  file.reset();
  apply_retention();
}

void BlackBox::apply_retention() {
  RetentionInput input;
  input.max_bytes = settings_.max_bytes;
  input.last_finished = last_finished_;
  if (incident_) input.being_written.push_back(part_name(incident_->name()));
  if (continuous_) input.being_written.push_back(part_name(continuous_->name()));
  try {
    input.files = files_.list();
    const RetentionPlan plan = plan_retention(input);
    for (const std::string& name : plan.remove) {
      files_.remove(name);
      spdlog::info("{} deleted: the files exceeded max_bytes ({})", name, settings_.max_bytes);
    }
    if (plan.kept_over_limit && plan.kept_over_limit->name != reported_over_limit_) {
      reported_over_limit_ = plan.kept_over_limit->name;
      spdlog::warn("{} ({} bytes) kept although the files add up to {} bytes, over max_bytes ({}): the newest "
                   "file is never deleted",
                   plan.kept_over_limit->name, plan.kept_over_limit->bytes, plan.bytes_kept, settings_.max_bytes);
    }
  } catch (const std::exception& error) {
    spdlog::error("retention: {}", error.what());
  }
}

}  // namespace wheeltec::record
