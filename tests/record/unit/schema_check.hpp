#pragma once

// Two readings of the recorder's JSON schemas, for the tests: a JSON Schema validator for
// the keywords they use, and Foxglove's way of reading one (its types only).

#include <string>
#include <vector>

#include "message_time.hpp"

namespace wheeltec::record::test {

// What is wrong with `value` by `schema` (type, properties, required, enum, items,
// minimum, maximum, minItems, maxItems, maxLength); empty when it is valid.
std::vector<std::string> schema_problems(const Json& schema, const Json& value, const std::string& path = "$");

// What Foxglove's JSON schema reader would refuse: an object without "properties", a
// member or array item whose "type" is not one of boolean, string, number, integer,
// object or array.
std::vector<std::string> foxglove_problems(const Json& schema, const std::string& path = "$");

}  // namespace wheeltec::record::test
