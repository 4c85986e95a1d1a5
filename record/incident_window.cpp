#include "incident_window.hpp"

#include <algorithm>

namespace wheeltec::record {

IncidentWindow::IncidentWindow(std::chrono::nanoseconds before, std::chrono::nanoseconds after)
    : before_(before), after_(after) {}

IncidentWindow::Recording IncidentWindow::open(const FiredTrigger& first) const {
  const RealtimeNanos end = first.trigger == Trigger::daemon_lost ? first.time : first.time + after_;
  return Recording{first.time - before_, end, {first}};
}

IncidentWindow::Change IncidentWindow::extend(Recording& recording, const FiredTrigger& fired) const {
  recording.triggers.push_back(fired);
  if (fired.trigger == Trigger::daemon_lost) {
    recording.end = std::max(recording.start, std::min(recording.end, fired.time));
    return Change::ends_now;
  }
  // The first window may itself be longer than kMaxSpan (before + after); it is not cut.
  const RealtimeNanos limit = std::max(recording.start + kMaxSpan, recording.end);
  const RealtimeNanos wanted = std::min(fired.time + after_, limit);
  if (wanted <= recording.end) return Change::joined;
  recording.end = wanted;
  return Change::extended;
}

IncidentWindow::TriggerResult IncidentWindow::on_trigger(const FiredTrigger& fired) {
  if (auto* recording = std::get_if<Recording>(&state_); recording && fired.time < recording->end) {
    return {extend(*recording, fired), std::nullopt};
  }
  std::optional<Recording> ended;
  if (auto* recording = std::get_if<Recording>(&state_)) ended = std::move(*recording);
  state_ = open(fired);
  return {Change::started, std::move(ended)};
}

std::optional<IncidentWindow::Recording> IncidentWindow::on_tick(RealtimeNanos now) {
  auto* recording = std::get_if<Recording>(&state_);
  if (!recording || now < recording->end) return std::nullopt;
  Recording done = std::move(*recording);
  state_ = Idle{};
  return done;
}

bool IncidentWindow::covers(RealtimeNanos time) const {
  const auto* recording = std::get_if<Recording>(&state_);
  return recording && recording->start <= time && time <= recording->end;
}

std::optional<RealtimeNanos> IncidentWindow::start() const {
  if (const auto* recording = std::get_if<Recording>(&state_)) return recording->start;
  return std::nullopt;
}

std::optional<RealtimeNanos> IncidentWindow::end() const {
  if (const auto* recording = std::get_if<Recording>(&state_)) return recording->end;
  return std::nullopt;
}

}  // namespace wheeltec::record
