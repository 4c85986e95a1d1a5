#pragma once

// Every JSON-RPC error code of wheeltec-gateway in one place (docs/api.md, "Error codes";
// docs/fleet.md for the bridges' own): the daemon answers with these, the client library
// names them, and the bridges answer with the same numbers. Header-only, no dependencies.

namespace wheeltec::error_codes {

// JSON-RPC 2.0's own.
inline constexpr int kParseError = -32700;
inline constexpr int kInvalidRequest = -32600;
inline constexpr int kMethodNotFound = -32601;
inline constexpr int kInvalidParams = -32602;
inline constexpr int kInternalError = -32603;

// wheeltecd's.
inline constexpr int kTooManyClients = -32000;   // on connecting, when api.max_clients are connected
inline constexpr int kControlHeld = -32001;      // another connection holds control
inline constexpr int kControlDisabled = -32002;  // drive after disable
inline constexpr int kBusDown = -32003;          // the link to the chassis is down (CAN or serial)
inline constexpr int kNoTelemetry = -32004;      // telemetry before the first record
inline constexpr int kNotPermitted = -32005;     // this user may not control the chassis
inline constexpr int kChassisNotReady = -32006;  // drive while the phase is booting, self-test or halted
inline constexpr int kEmergencyStopLatched = -32007;  // drive, enable or release while the emergency stop holds (protocol 5)

// The bridges' (a bridge answers its own clients on behalf of the daemon).
inline constexpr int kTooManyOperators = -32009;   // wheeltec-mqtt: every operator slot is taken
inline constexpr int kDaemonUnreachable = -32008;  // wheeltecd cannot be reached, or gave no answer

// A short English name of `code`, for messages; nullptr for a code not listed here.
constexpr const char* describe(int code) {
  switch (code) {
    case kParseError: return "parse error";
    case kInvalidRequest: return "invalid request";
    case kMethodNotFound: return "unknown method";
    case kInvalidParams: return "invalid params";
    case kInternalError: return "internal error";
    case kTooManyClients: return "too many clients";
    case kControlHeld: return "another client holds control";
    case kControlDisabled: return "control is disabled";
    case kBusDown: return "the link to the chassis is down";
    case kNoTelemetry: return "no telemetry yet";
    case kNotPermitted: return "not allowed to control the chassis";
    case kChassisNotReady: return "the chassis is not ready (booting, self-test or halted)";
    case kEmergencyStopLatched: return "the emergency stop is latched";
    case kTooManyOperators: return "too many remote operators";
    case kDaemonUnreachable: return "wheeltecd is not reachable";
    default: return nullptr;
  }
}

}  // namespace wheeltec::error_codes
