#pragma once

#include "wheeltec/backoff.hpp"

namespace wheeltec::client {

using Backoff = wheeltec::Backoff;

}  // namespace wheeltec::client
