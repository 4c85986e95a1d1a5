#include "arguments.hpp"

#include <charconv>
#include <cmath>

#include "wheeltec/client/connection.hpp"

namespace wheeltecctl {

std::string resolve_socket_path(const std::optional<std::string>& option) {
  return option ? *option : wheeltec::client::socket_path_from_environment();
}

std::optional<double> parse_finite_number(std::string_view text) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  if (text.empty()) return std::nullopt;
  double value = 0.0;
  const char* const end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(text.data(), end, value);
  if (error != std::errc{} || stop != end || !std::isfinite(value)) return std::nullopt;
  return value;
}

std::variant<wheeltec::Velocity, std::string> parse_drive_velocity(
    const std::vector<std::string>& positionals) {
  if (positionals.size() != 2 && positionals.size() != 3) {
    return std::string("drive needs VX WZ or VX VY WZ");
  }
  std::vector<double> numbers;
  for (const auto& text : positionals) {
    const auto number = parse_finite_number(text);
    if (!number) return "drive: '" + text + "' is not a number";
    numbers.push_back(*number);
  }
  if (numbers.size() == 2) return wheeltec::Velocity{numbers[0], 0.0, numbers[1]};
  return wheeltec::Velocity{numbers[0], numbers[1], numbers[2]};
}

}  // namespace wheeltecctl
