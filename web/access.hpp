#pragma once

// Who may do what on wheeltec-web (spec section 6): the driving token, the Origin check
// of WebSocket upgrades, and the parts of a request target they read. Pure: no I/O.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace wheeltec::web {

// "Bearer TOKEN" (scheme case-insensitive) -> TOKEN.
std::optional<std::string> bearer_token(std::string_view authorization);

// The path of a request target ("/foxglove?token=x" -> "/foxglove").
std::string_view target_path(std::string_view target);

// The percent-decoded value of `name` in the target's query, if present.
std::optional<std::string> query_parameter(std::string_view target, std::string_view name);

// Equal, in a time that does not depend on where they differ.
bool tokens_equal(std::string_view given, std::string_view expected);

// Whether a WebSocket upgrade with this Origin header may proceed: none (a desktop
// client), the server's own origin (http(s)://HOST where HOST is the request's Host
// header), or one of `allowed` (compared without case and trailing slash).
bool origin_allowed(std::optional<std::string_view> origin, std::string_view host,
                    const std::vector<std::string>& allowed);

// Whether a Host header names this machine's loopback: localhost, 127.x.y.z or [::1], with
// or without a port. A page of another site that rebinds its DNS name to 127.0.0.1 reaches
// the server from the loopback too, but under its own name: trusting the loopback address
// alone would let any web page open on the robot drive it.
bool is_loopback_host(std::string_view host);

// Whether a Sec-WebSocket-Protocol header (a comma-separated list) offers `protocol`.
bool offers_subprotocol(std::string_view header, std::string_view protocol);

// The token file's content with surrounding whitespace stripped.
std::string token_from_file_content(std::string_view content);

}  // namespace wheeltec::web
