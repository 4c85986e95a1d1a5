#pragma once

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <functional>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include "ros2_side/participant.hpp"
#include "ros2_side/qos_profiles.hpp"

namespace ros2_side {

using WallClock = std::chrono::system_clock;

template <class Message>
struct Received {
  Message message;
  WallClock::time_point arrival;
};

// A DataReader of one topic ("rt/odom") that keeps every sample it receives with the time
// it arrived. `Type` is a TopicDataType whose `type` is the message, as fastddsgen makes them.
template <class Type>
class TopicReader : private eprosima::fastdds::dds::DataReaderListener {
 public:
  using Message = typename Type::type;
  using Sample = Received<Message>;
  using SamplePredicate = std::function<bool(const Sample&)>;

  TopicReader(Participant& participant, const std::string& topic, RosQos profile)
      : participant_(participant), topic_(topic) {
    auto& dds_topic = participant.topic(topic, eprosima::fastdds::dds::TypeSupport(new Type()));
    reader_ = participant.subscriber().create_datareader(&dds_topic, reader_qos(profile), this);
    if (reader_ == nullptr) throw std::runtime_error("Fast DDS: cannot create a reader of " + topic);
  }

  ~TopicReader() override {
    reader_->set_listener(nullptr);
    participant_.subscriber().delete_datareader(reader_);
  }

  TopicReader(const TopicReader&) = delete;
  TopicReader& operator=(const TopicReader&) = delete;

  const std::string& topic() const { return topic_; }

  std::vector<Sample> samples() const {
    std::lock_guard lock(mutex_);
    return samples_;
  }

  // Every sample so far, once there are at least `count` or `timeout` has passed.
  std::vector<Sample> wait_for_count(std::size_t count, std::chrono::milliseconds timeout) const {
    std::unique_lock lock(mutex_);
    changed_.wait_for(lock, timeout, [&] { return samples_.size() >= count; });
    return samples_;
  }

  // The first sample, received before or within `timeout`, that satisfies `matches`.
  std::optional<Sample> wait_for(const SamplePredicate& matches, std::chrono::milliseconds timeout) const {
    std::unique_lock lock(mutex_);
    std::optional<Sample> found;
    std::size_t checked = 0;
    changed_.wait_for(lock, timeout, [&] {
      for (; checked < samples_.size() && !found; ++checked) {
        if (matches(samples_[checked])) found = samples_[checked];
      }
      return found.has_value();
    });
    return found;
  }

  // Whether a writer of this topic has matched within `timeout`.
  bool wait_matched(std::chrono::milliseconds timeout) const {
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, timeout, [&] { return matched_writers_ > 0; });
  }

 private:
  void on_data_available(eprosima::fastdds::dds::DataReader* reader) override {
    Message message;
    eprosima::fastdds::dds::SampleInfo info;
    while (reader->take_next_sample(&message, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      {
        std::lock_guard lock(mutex_);
        samples_.push_back({message, WallClock::now()});
      }
      changed_.notify_all();
    }
  }

  void on_subscription_matched(eprosima::fastdds::dds::DataReader*,
                               const eprosima::fastdds::dds::SubscriptionMatchedStatus& status) override {
    {
      std::lock_guard lock(mutex_);
      matched_writers_ = status.current_count;
    }
    changed_.notify_all();
  }

  Participant& participant_;
  std::string topic_;
  eprosima::fastdds::dds::DataReader* reader_ = nullptr;
  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  std::vector<Sample> samples_;
  int matched_writers_ = 0;
};

}  // namespace ros2_side
