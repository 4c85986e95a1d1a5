#include "mcap_records.hpp"

#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <stdexcept>

#include "wheeltec/mcap/little_endian.hpp"

namespace mcap_test {

using wheeltec::mcap::get_le;

std::vector<RawRecord> split_records(ByteView bytes, std::uint64_t first_offset) {
  std::vector<RawRecord> records;
  std::uint64_t at = 0;
  while (at < bytes.size()) {
    if (bytes.size() - at < 9) throw std::runtime_error("a record head is cut at offset " + std::to_string(at));
    const std::uint64_t length = get_le<std::uint64_t>(bytes.data() + at + 1);
    if (length > bytes.size() - at - 9) {
      throw std::runtime_error("the record at offset " + std::to_string(first_offset + at) + " runs past the end");
    }
    records.push_back(RawRecord{std::to_integer<std::uint8_t>(bytes[at]), first_offset + at,
                                bytes.subspan(at + 9, length)});
    at += 9 + length;
  }
  return records;
}

ByteView FieldReader::take(std::uint64_t size) {
  if (size > rest_.size()) throw std::runtime_error("a field runs past the end of its record");
  const ByteView field = rest_.first(size);
  rest_ = rest_.subspan(size);
  return field;
}

std::uint8_t FieldReader::u8() { return std::to_integer<std::uint8_t>(take(1)[0]); }
std::uint16_t FieldReader::u16() { return get_le<std::uint16_t>(take(2).data()); }
std::uint32_t FieldReader::u32() { return get_le<std::uint32_t>(take(4).data()); }
std::uint64_t FieldReader::u64() { return get_le<std::uint64_t>(take(8).data()); }
ByteView FieldReader::bytes32() { return take(u32()); }
ByteView FieldReader::bytes64() { return take(u64()); }
std::string FieldReader::string() { return as_text(bytes32()); }

ByteView FieldReader::rest() { return take(rest_.size()); }

std::map<std::string, std::string> FieldReader::string_map() {
  FieldReader entries(bytes32());
  std::map<std::string, std::string> map;
  while (!entries.at_end()) {
    std::string key = entries.string();
    map[key] = entries.string();
  }
  return map;
}

std::map<std::uint16_t, std::uint64_t> FieldReader::u16_u64_map() {
  FieldReader entries(bytes32());
  std::map<std::uint16_t, std::uint64_t> map;
  while (!entries.at_end()) {
    const std::uint16_t key = entries.u16();
    map[key] = entries.u64();
  }
  return map;
}

std::vector<std::pair<std::uint64_t, std::uint64_t>> FieldReader::u64_pairs() {
  FieldReader items(bytes32());
  std::vector<std::pair<std::uint64_t, std::uint64_t>> pairs;
  while (!items.at_end()) {
    const std::uint64_t first = items.u64();
    pairs.emplace_back(first, items.u64());
  }
  return pairs;
}

Bytes zstd_decompress(ByteView compressed, std::uint64_t uncompressed_size) {
  Bytes out(uncompressed_size);
  const std::size_t size = ZSTD_decompress(out.data(), out.size(), compressed.data(), compressed.size());
  if (ZSTD_isError(size) != 0) throw std::runtime_error(std::string("zstd: ") + ZSTD_getErrorName(size));
  if (size != uncompressed_size) throw std::runtime_error("the chunk decompresses to another size");
  return out;
}

std::uint32_t crc32_of(ByteView bytes) {
  return static_cast<std::uint32_t>(
      ::crc32(0, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<uInt>(bytes.size())));
}

bool same_bytes(ByteView a, ByteView b) { return std::equal(a.begin(), a.end(), b.begin(), b.end()); }

std::string as_text(ByteView bytes) { return std::string(reinterpret_cast<const char*>(bytes.data()), bytes.size()); }

}  // namespace mcap_test
