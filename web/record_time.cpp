#include "record_time.hpp"

#include <cstddef>
#include <string>

#include <nlohmann/json.hpp>

namespace wheeltec::web {
namespace {

// nlohmann's SAX events, stopped (by returning false) as soon as the answer is known.
class TimeReader {
 public:
  using Json = nlohmann::json;

  std::optional<double> time;

  bool null() { return value_is_not_a_number(); }
  bool boolean(bool) { return value_is_not_a_number(); }
  bool number_integer(Json::number_integer_t value) { return number(static_cast<double>(value)); }
  bool number_unsigned(Json::number_unsigned_t value) { return number(static_cast<double>(value)); }
  bool number_float(Json::number_float_t value, const std::string&) { return number(value); }
  bool string(std::string&) { return value_is_not_a_number(); }
  bool binary(Json::binary_t&) { return value_is_not_a_number(); }
  bool start_object(std::size_t) {
    if (at_time_) return false;  // "time" is an object
    ++depth_;
    return true;
  }
  bool end_object() {
    --depth_;
    return depth_ > 0;  // the record ended without "time"
  }
  bool start_array(std::size_t) {
    if (at_time_ || depth_ == 0) return false;  // "time" is an array, or the record is not an object
    ++depth_;
    return true;
  }
  bool end_array() {
    --depth_;
    return true;
  }
  bool key(std::string& name) {
    at_time_ = depth_ == 1 && name == "time";
    return true;
  }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) { return false; }

 private:
  bool number(double value) {
    if (!at_time_) return depth_ > 0;
    time = value;
    return false;
  }
  bool value_is_not_a_number() { return !at_time_ && depth_ > 0; }

  int depth_ = 0;
  bool at_time_ = false;
};

}  // namespace

std::optional<double> record_time(std::string_view record) {
  TimeReader reader;
  nlohmann::json::sax_parse(record.begin(), record.end(), &reader);
  return reader.time;
}

}  // namespace wheeltec::web
