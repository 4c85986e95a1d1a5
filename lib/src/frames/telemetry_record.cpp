#include "wheeltec/frames/telemetry_record.hpp"

#include <bit>
#include <cstring>

#include "wheeltec/frames/big_endian.hpp"

namespace wheeltec {

namespace {

constexpr std::size_t kChecksumIndex = 22;
constexpr std::size_t kTailIndex = 23;

std::int16_t get_be16(const RecordBytes& bytes, std::size_t at) { return wheeltec::get_be16(&bytes[at]); }

void put_be16(RecordBytes& bytes, std::size_t at, std::int16_t value) { wheeltec::put_be16(&bytes[at], value); }

}  // namespace

std::uint8_t block_check(const std::uint8_t* bytes, std::size_t n) {
  // Eight bytes at a time, then the eight byte lanes folded into one: XOR does not care
  // about order, so this is the same sum as byte by byte, in about a quarter of the steps.
  std::uint64_t lanes = 0;
  std::size_t i = 0;
  for (; i + sizeof(lanes) <= n; i += sizeof(lanes)) {
    std::uint64_t word;
    std::memcpy(&word, bytes + i, sizeof(word));
    lanes ^= word;
  }
  lanes ^= lanes >> 32;
  lanes ^= lanes >> 16;
  lanes ^= lanes >> 8;
  auto sum = static_cast<std::uint8_t>(lanes);
  for (; i < n; ++i) sum ^= bytes[i];
  return sum;
}

namespace {

// True if the XOR of bytes 0..21 equals byte 22, i.e. bytes 0..22 XOR to zero: three word
// loads, the third with the tail masked off, folded to one byte. Bytes 0..7 of a word are
// its low to high bytes on a little-endian host; elsewhere the plain byte sum is used.
bool checksum_matches(const RecordBytes& bytes) {
  if constexpr (std::endian::native == std::endian::little) {
    // Word by word: the reassembler stores the record as three 8-byte frames, and a wider
    // load spanning two of them would stall on store forwarding.
    std::uint64_t words[3];
    static_assert(sizeof(words) == kRecordSize);
    for (std::size_t i = 0; i < 3; ++i) std::memcpy(&words[i], bytes.data() + 8 * i, sizeof(words[i]));
    std::uint64_t lanes = words[0] ^ words[1] ^ (words[2] & 0x00FF'FFFF'FFFF'FFFFull);
    lanes ^= lanes >> 32;
    lanes ^= lanes >> 16;
    lanes ^= lanes >> 8;
    return static_cast<std::uint8_t>(lanes) == 0;
  } else {
    return bytes[kChecksumIndex] == block_check(bytes.data(), kChecksumIndex);
  }
}

}  // namespace

RecordFault check_record(const RecordBytes& bytes) {
  if (bytes[0] != kRecordHeader) return RecordFault::bad_header;
  if (bytes[kTailIndex] != kRecordTail) return RecordFault::bad_tail;
  if (!checksum_matches(bytes)) return RecordFault::bad_checksum;
  return RecordFault::none;
}

RawTelemetry decode_raw(const RecordBytes& bytes) {
  RawTelemetry raw;
  raw.flag_stop = bytes[1];
  raw.vx = get_be16(bytes, 2);
  raw.vy = get_be16(bytes, 4);
  raw.vz = get_be16(bytes, 6);
  raw.accel_x = get_be16(bytes, 8);
  raw.accel_y = get_be16(bytes, 10);
  raw.accel_z = get_be16(bytes, 12);
  raw.gyro_x = get_be16(bytes, 14);
  raw.gyro_y = get_be16(bytes, 16);
  raw.gyro_z = get_be16(bytes, 18);
  raw.battery_mv = get_be16(bytes, 20);
  return raw;
}

TelemetryRecord to_physical(const RawTelemetry& raw) {
  TelemetryRecord record;
  record.stopped = raw.flag_stop != 0;
  record.velocity = {raw.vx / 1000.0, raw.vy / 1000.0, raw.vz / 1000.0};
  record.accel = {raw.accel_x / kAccelLsbPerMps2, raw.accel_y / kAccelLsbPerMps2,
                  raw.accel_z / kAccelLsbPerMps2};
  record.gyro = {raw.gyro_x / kGyroLsbPerRadps, raw.gyro_y / kGyroLsbPerRadps,
                 raw.gyro_z / kGyroLsbPerRadps};
  record.battery_v = raw.battery_mv / 1000.0;
  return record;
}

RecordBytes encode_record(const RawTelemetry& raw) {
  RecordBytes bytes{};
  bytes[0] = kRecordHeader;
  bytes[1] = raw.flag_stop;
  put_be16(bytes, 2, raw.vx);
  put_be16(bytes, 4, raw.vy);
  put_be16(bytes, 6, raw.vz);
  put_be16(bytes, 8, raw.accel_x);
  put_be16(bytes, 10, raw.accel_y);
  put_be16(bytes, 12, raw.accel_z);
  put_be16(bytes, 14, raw.gyro_x);
  put_be16(bytes, 16, raw.gyro_y);
  put_be16(bytes, 18, raw.gyro_z);
  put_be16(bytes, 20, raw.battery_mv);
  bytes[kChecksumIndex] = block_check(bytes.data(), kChecksumIndex);
  bytes[kTailIndex] = kRecordTail;
  return bytes;
}

}  // namespace wheeltec
