#pragma once

#include <chrono>

#include "wheeltec/clocks.hpp"

namespace wheeltec::record::test {

// Where the tests' times start: 2026-11-24T20:34:20Z, the second of docs/api.md's record.
inline const RealtimeNanos t0{std::chrono::seconds(1'795'552'460)};

}  // namespace wheeltec::record::test
