#include "wheeltec/config/json_text.hpp"

#include <set>
#include <vector>

#include <fmt/format.h>

namespace wheeltec::json_text {
namespace {

using json = nlohmann::json;

// The containers open at a point of the parse, outermost first.
class OpenContainers {
 public:
  void enter_element() {
    if (!frames_.empty() && frames_.back().is_array) ++frames_.back().elements;
  }
  void open(bool is_array) { frames_.push_back(Frame{is_array, {}, 0, {}}); }
  void close() {
    if (!frames_.empty()) frames_.pop_back();
  }
  // False when the key repeats one of its object's.
  bool add_key(const std::string& key) {
    if (frames_.empty() || frames_.back().is_array) return true;  // inside a dropped container
    Frame& frame = frames_.back();
    frame.key = key;
    return frame.keys.insert(key).second;
  }
  std::string path() const {
    std::string out;
    for (const Frame& frame : frames_) {
      if (frame.is_array) {
        out += fmt::format("[{}]", frame.elements - 1);
      } else {
        if (!out.empty()) out += '.';
        out += frame.key;
      }
    }
    return out;
  }

 private:
  struct Frame {
    bool is_array;
    std::string key;           // objects: the member being parsed
    std::size_t elements;      // arrays: elements started so far
    std::set<std::string> keys;
  };
  std::vector<Frame> frames_;
};

}  // namespace

json parse(std::string_view text, Findings& findings, int max_depth) {
  findings = Findings{};
  // Only kept containers are tracked: nlohmann reports no end for a dropped one. Keys
  // inside a dropped container may then be checked against an outer object, but
  // too_deep is the finding that counts.
  OpenContainers open;
  return json::parse(text.begin(), text.end(), [&](int depth, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
      case json::parse_event_t::array_start:
        if (depth >= max_depth) {
          findings.too_deep = true;
          return false;
        }
        open.enter_element();
        open.open(event == json::parse_event_t::array_start);
        return true;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        open.close();
        return true;
      case json::parse_event_t::value:
        open.enter_element();
        return true;
      case json::parse_event_t::key:
        if (parsed.is_string() && !open.add_key(parsed.get_ref<const std::string&>()) && !findings.duplicate_key) {
          findings.duplicate_key = parsed.get<std::string>();
          findings.duplicate_path = open.path();
          findings.duplicate_depth = depth;
        }
        return true;
    }
    return true;
  });
}

StrictRead read_strict(std::string_view text, int max_depth) {
  StrictRead read;
  try {
    read.document = parse(text, read.findings, max_depth);
  } catch (const json::exception& error) {
    read.document = nullptr;
    read.syntax_error = message(error);
  }
  if (read.findings.too_deep) {
    read.refusal = Refusal{Refusal::Reason::too_deep, fmt::format("nested deeper than {} levels", max_depth)};
  } else if (read.syntax_error) {
    read.refusal = Refusal{Refusal::Reason::not_json, *read.syntax_error};
  } else if (read.findings.duplicate_key) {
    read.refusal = Refusal{Refusal::Reason::duplicate_key,
                           fmt::format("duplicate key \"{}\"", printable(*read.findings.duplicate_key))};
  }
  return read;
}

std::string message(const json::exception& error) {
  std::string_view what = error.what();
  const auto bracket = what.find("] ");
  if (what.starts_with("[json.exception.") && bracket != std::string_view::npos) what.remove_prefix(bracket + 2);
  return printable(what);
}

std::string printable(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char ch : text) {
    const auto byte = static_cast<unsigned char>(ch);
    if (byte < 0x20 || byte >= 0x7F) {
      out += fmt::format("\\x{:02X}", byte);
    } else {
      out += ch;
    }
  }
  return out;
}

}  // namespace wheeltec::json_text
