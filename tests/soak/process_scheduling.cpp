#include "process_scheduling.hpp"

#include <sched.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace integration {

Scheduling Scheduling::parse(const std::string& text) {
  const auto colon = text.find(':');
  if (colon == std::string::npos) {
    throw std::invalid_argument("scheduling '" + text + "' is not nice:N, rr:N or fifo:N");
  }
  const std::string name = text.substr(0, colon);
  Scheduling scheduling;
  if (name == "nice") {
    scheduling.policy = normal;
  } else if (name == "rr") {
    scheduling.policy = round_robin;
  } else if (name == "fifo") {
    scheduling.policy = fifo;
  } else {
    throw std::invalid_argument("scheduling policy '" + name + "' is not nice, rr or fifo");
  }
  std::size_t used = 0;
  const std::string number = text.substr(colon + 1);
  try {
    scheduling.value = std::stoi(number, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != number.size()) {
    throw std::invalid_argument("scheduling value '" + number + "' is not an integer");
  }
  const bool in_range = scheduling.policy == normal ? scheduling.value >= -20 && scheduling.value <= 19
                                                    : scheduling.value >= 1 && scheduling.value <= 99;
  if (!in_range) throw std::invalid_argument("scheduling value out of range in '" + text + "'");
  return scheduling;
}

std::string Scheduling::describe() const {
  switch (policy) {
    case round_robin: return "SCHED_RR priority " + std::to_string(value);
    case fifo: return "SCHED_FIFO priority " + std::to_string(value);
    default: return "nice " + std::to_string(value);
  }
}

Scheduling one_step_ahead(const Scheduling& scheduling) {
  Scheduling ahead = scheduling;
  ahead.value = scheduling.policy == Scheduling::normal ? std::max(-20, scheduling.value - 1)
                                                        : std::min(99, scheduling.value + 1);
  return ahead;
}

// "rr:N" or "fifo:N" from a command line such as `-+/usr/bin/chrt --rr --all-tasks --pid 10 $MAINPID`.
static std::string chrt_scheduling(const std::string& command) {
  std::istringstream words(command);
  std::string word;
  std::string policy;
  std::string priority;
  while (words >> word) {
    if (word == "--rr" || word == "-r") policy = "rr";
    if (word == "--fifo" || word == "-f") policy = "fifo";
    if (priority.empty() && !word.empty() && word.find_first_not_of("0123456789") == std::string::npos) priority = word;
  }
  if (policy.empty() || priority.empty()) {
    throw std::invalid_argument("ExecStartPost=" + command + ": chrt without --rr/--fifo and a priority");
  }
  return policy + ":" + priority;
}

std::optional<Scheduling> scheduling_of_unit(const std::filesystem::path& unit) {
  std::ifstream file(unit);
  if (!file) throw std::runtime_error("cannot read " + unit.string());
  std::optional<std::string> nice;
  std::optional<std::string> policy;
  std::optional<std::string> priority;
  std::optional<std::string> raise_command;  // an ExecStartPost= chrt
  std::string line;
  while (std::getline(file, line)) {
    const auto equals = line.find('=');
    if (line.empty() || line[0] == '#' || equals == std::string::npos) continue;
    const std::string key = line.substr(0, equals);
    const std::string value = line.substr(equals + 1);
    if (key == "Nice") nice = value;
    if (key == "CPUSchedulingPolicy") policy = value;
    if (key == "CPUSchedulingPriority") priority = value;
    if (key == "ExecStartPost" && value.find("chrt") != std::string::npos) raise_command = value;
  }
  try {
    // chrt raises the started daemon where the kernel allows it: that is what is soaked.
    if (raise_command) return Scheduling::parse(chrt_scheduling(*raise_command));
    if (policy && (*policy == "rr" || *policy == "fifo")) {
      return Scheduling::parse(*policy + ":" + priority.value_or("1"));
    }
    if (policy && *policy != "other") {
      throw std::invalid_argument("CPUSchedulingPolicy=" + *policy + " is not rr, fifo or other");
    }
    if (nice) return Scheduling::parse("nice:" + *nice);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(unit.string() + ": " + error.what());
  }
  return std::nullopt;
}

namespace {

void apply_to_thread(const Scheduling& scheduling, pid_t thread) {
  int result = 0;
  if (scheduling.policy == Scheduling::normal) {
    result = ::setpriority(PRIO_PROCESS, static_cast<id_t>(thread), scheduling.value);
  } else {
    sched_param parameter{};
    parameter.sched_priority = scheduling.value;
    result = ::sched_setscheduler(thread, scheduling.policy == Scheduling::fifo ? SCHED_FIFO : SCHED_RR, &parameter);
  }
  if (result != 0) {
    throw std::runtime_error("cannot set " + scheduling.describe() + " on thread " + std::to_string(thread) + ": " +
                             std::strerror(errno));
  }
}

}  // namespace

void apply_to_process(const Scheduling& scheduling, pid_t pid) {
  for (const auto& task : std::filesystem::directory_iterator("/proc/" + std::to_string(pid) + "/task")) {
    apply_to_thread(scheduling, static_cast<pid_t>(std::stoi(task.path().filename().string())));
  }
}

void apply_to_this_thread(const Scheduling& scheduling) { apply_to_thread(scheduling, ::gettid()); }

}  // namespace integration
