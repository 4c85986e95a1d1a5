#pragma once

// The emergency stop as wheeltec-web takes it (spec section 12, Bridges): the params of an
// `estop` from a POST body or a Foxglove payload, and how a daemon's refusal is answered
// over HTTP. Pure: no I/O.

#include <string>
#include <string_view>
#include <variant>

#include "wheeltec/client/records.hpp"

namespace wheeltec::web {

using client::Json;

// Why a request is not passed on, worded for the one who sent it.
struct RequestProblem {
  std::string message;
};

// Empty (or only whitespace): `{}`; a JSON object: `{"reason": TEXT}` when it has a string
// `reason`, else `{}` (other keys are not the daemon's business). Anything else (not JSON,
// not an object, a reason that is not a string): what is wrong, for the caller.
std::variant<Json, RequestProblem> estop_params(std::string_view body);

// The HTTP status that answers the daemon's JSON-RPC error `code` on /api/estop and
// /api/release: 400 bad params, 403 not permitted, 409 latched (-32007), 503 unreachable,
// 502 for anything else the daemon said.
unsigned http_status_of_rpc_error(int code);

// `{"code": CODE, "message": MESSAGE}`: the body of an answer wheeltec-web makes itself in
// the daemon's error shape.
Json rpc_error_body(int code, std::string_view message);

}  // namespace wheeltec::web
