#include "wheeltec/telemetry/telemetry_json.hpp"

#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>
#include <system_error>

#include "wheeltec/frames/fixed_decimal.hpp"

namespace wheeltec {
namespace {

// The longest fixed-point double (DBL_MAX) has 309 integer digits; with sign, point and 6
// decimals, 317 characters. A record has 20 such numbers and under 512 other characters.
constexpr std::size_t kLongestFixed = 317;
constexpr std::size_t kLongestRecord = 20 * kLongestFixed + 512;

// Writes a record into one stack buffer, which then goes into the string in one append:
// a string with enough capacity is never reallocated (the daemon reuses one per record).
class RecordWriter {
 public:
  void text(std::string_view s) {
    std::memcpy(end_, s.data(), s.size());
    end_ += s.size();
  }

  void integer(std::uint64_t value) { end_ = std::to_chars(end_, end_ + 24, value).ptr; }

  void boolean(bool value) { text(value ? std::string_view("true") : std::string_view("false")); }

  template <int Decimals>
  void fixed(double value) {
    using fixed_decimal_detail::NegativeZero;
    char* const end = fixed_decimal_detail::write_small_fixed<Decimals, NegativeZero::unsigned_>(end_, value);
    if (end != nullptr) {
      end_ = end;
    } else {
      any_fixed<Decimals>(value);
    }
  }

  template <int Decimals>
  [[gnu::noinline]] void any_fixed(double value) {
    if (!std::isfinite(value)) {
      text("null");  // JSON has no NaN or infinity
      return;
    }
    char* const begin = end_;
    const auto result = fixed_decimal_to_chars<Decimals>(begin, begin + kLongestFixed, value);
    if (result.ec != std::errc{}) {
      text("null");
      return;
    }
    end_ = result.ptr;
    // -0.0 and tiny negatives that round to zero print as 0.000: "-" then exactly that.
    constexpr std::string_view kZero = std::string_view("0.000000000").substr(0, Decimals > 0 ? 2 + Decimals : 1);
    if (*begin == '-' && end_ - begin == static_cast<std::ptrdiff_t>(1 + kZero.size()) &&
        std::memcmp(begin + 1, kZero.data(), kZero.size()) == 0) {
      std::memmove(begin, begin + 1, kZero.size());
      --end_;
    }
  }

  template <int Decimals>
  void member(std::string_view key_with_quotes_and_colon, double value) {
    text(key_with_quotes_and_colon);
    fixed<Decimals>(value);
  }

  template <int Decimals>
  void vector(const Vector3& v) {
    member<Decimals>("{\"x\":", v.x);
    member<Decimals>(",\"y\":", v.y);
    member<Decimals>(",\"z\":", v.z);
    text("}");
  }

  // Seconds since the epoch with 6 decimals, from integer nanoseconds (no rounding of a
  // double: the microseconds are the kernel's).
  void time(RealtimeNanos time) { end_ = write_seconds_from_nanos(end_, time.time_since_epoch().count()); }

  void append_to(std::string& out) const { out.append(buffer_, static_cast<std::size_t>(end_ - buffer_)); }

 private:
  char buffer_[kLongestRecord];
  char* end_ = buffer_;
};

void write_record(RecordWriter& w, const TelemetrySample& sample) {
  const TelemetryRecord& r = sample.record;
  w.text("{\"seq\":");
  w.integer(sample.seq);
  w.text(",\"time\":");
  w.time(sample.time);
  w.text(",\"stopped\":");
  w.boolean(r.stopped);

  w.member<3>(",\"velocity\":{\"vx\":", r.velocity.vx);
  w.member<3>(",\"vy\":", r.velocity.vy);
  w.member<3>(",\"wz\":", r.velocity.wz);

  w.text("},\"accel\":");
  w.vector<4>(r.accel);
  w.text(",\"gyro\":");
  w.vector<5>(r.gyro);

  w.member<3>(",\"battery\":{\"voltage\":", r.battery_v);
  w.text(",\"low\":");
  w.boolean(sample.battery_low);

  w.member<6>("},\"odom\":{\"x\":", sample.odom.x);
  w.member<6>(",\"y\":", sample.odom.y);
  w.member<6>(",\"yaw\":", sample.odom.yaw);

  const Orientation& o = sample.orientation;
  w.member<6>("},\"orientation\":{\"w\":", o.w);
  w.member<6>(",\"x\":", o.x);
  w.member<6>(",\"y\":", o.y);
  w.member<6>(",\"z\":", o.z);
  w.member<6>(",\"roll\":", o.roll);
  w.member<6>(",\"pitch\":", o.pitch);
  w.member<6>(",\"yaw\":", o.yaw);
  w.text("}}");
}

}  // namespace

void append_telemetry_json(std::string& out, const TelemetrySample& sample) {
  RecordWriter writer;
  write_record(writer, sample);
  writer.append_to(out);
}

void append_telemetry_notification(std::string& out, const TelemetrySample& sample) {
  RecordWriter writer;
  writer.text("{\"jsonrpc\":\"2.0\",\"method\":\"telemetry\",\"params\":");
  write_record(writer, sample);
  writer.text("}\n");
  writer.append_to(out);
}

}  // namespace wheeltec
