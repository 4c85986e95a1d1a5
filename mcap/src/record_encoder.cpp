#include "record_encoder.hpp"

#include <limits>
#include <string>

#include "wheeltec/mcap/little_endian.hpp"

namespace wheeltec::mcap {
namespace {

constexpr std::size_t kOpcodeAndLength = 1 + 8;

void check_length32(std::uint64_t size, std::string_view what) {
  if (size > std::numeric_limits<std::uint32_t>::max()) {
    throw Error(std::string(what) + " of " + std::to_string(size) + " bytes is longer than MCAP's uint32 length");
  }
}

}  // namespace

RecordEncoder::RecordEncoder(Bytes& out, Opcode opcode) : out_(out), start_(out.size()) {
  out_.push_back(static_cast<std::byte>(opcode));
  append_le<std::uint64_t>(out_, 0);
}

RecordEncoder& RecordEncoder::u8(std::uint8_t value) {
  out_.push_back(static_cast<std::byte>(value));
  return *this;
}

RecordEncoder& RecordEncoder::u16(std::uint16_t value) {
  append_le(out_, value);
  return *this;
}

RecordEncoder& RecordEncoder::u32(std::uint32_t value) {
  append_le(out_, value);
  return *this;
}

RecordEncoder& RecordEncoder::u64(std::uint64_t value) {
  append_le(out_, value);
  return *this;
}

RecordEncoder& RecordEncoder::string(std::string_view text) { return bytes32(text_bytes(text)); }

RecordEncoder& RecordEncoder::bytes32(ByteView bytes) {
  check_length32(bytes.size(), "a string or bytes field");
  u32(static_cast<std::uint32_t>(bytes.size()));
  return raw(bytes);
}

RecordEncoder& RecordEncoder::raw(ByteView bytes) {
  out_.insert(out_.end(), bytes.begin(), bytes.end());
  return *this;
}

RecordEncoder& RecordEncoder::string_map(const Metadata& map) {
  const std::size_t at = begin_length32();
  for (const auto& [key, value] : map) string(key).string(value);
  end_length32(at);
  return *this;
}

std::size_t RecordEncoder::begin_length32() {
  const std::size_t at = out_.size();
  append_le<std::uint32_t>(out_, 0);
  return at;
}

void RecordEncoder::end_length32(std::size_t at) {
  const std::uint64_t size = out_.size() - at - 4;
  check_length32(size, "a map or array");
  put_le(out_.data() + at, static_cast<std::uint32_t>(size));
}

std::size_t RecordEncoder::finish(std::uint64_t trailing) {
  const std::size_t size = out_.size() - start_;
  put_le(out_.data() + start_ + 1, static_cast<std::uint64_t>(size - kOpcodeAndLength + trailing));
  return size;
}

}  // namespace wheeltec::mcap
