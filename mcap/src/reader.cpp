#include "wheeltec/mcap/reader.hpp"

#include <zstd.h>

#include <string_view>

#include "crc32.hpp"
#include "wheeltec/mcap/little_endian.hpp"

namespace wheeltec::mcap {
namespace {

constexpr std::byte kMagic[] = {std::byte{0x89}, std::byte{'M'}, std::byte{'C'},  std::byte{'A'},
                                std::byte{'P'},  std::byte{'0'}, std::byte{'\r'}, std::byte{'\n'}};
constexpr std::size_t kMagicSize = sizeof(kMagic);
constexpr std::size_t kRecordHead = 9;  // opcode, uint64 length

enum Op : std::uint8_t {
  kHeader = 0x01, kFooter = 0x02, kSchema = 0x03, kChannel = 0x04, kMessage = 0x05, kChunk = 0x06,
  kAttachment = 0x09, kMetadata = 0x0C, kDataEnd = 0x0F,
};

std::string hex(std::uint32_t value) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string out = "0x";
  for (int shift = 28; shift >= 0; shift -= 4) out.push_back(kDigits[(value >> shift) & 0xF]);
  return out;
}

[[noreturn]] void fail(std::uint64_t offset, const std::string& what) {
  throw ReadError("byte " + std::to_string(offset) + ": " + what);
}

// The fields of one record's content, each read only when the content still holds it.
class Fields {
 public:
  Fields(ByteView content, std::uint64_t offset, const char* record)
      : content_(content), offset_(offset), record_(record) {}

  template <typename Unsigned>
  Unsigned number(const char* field) {
    need(sizeof(Unsigned), field);
    const Unsigned value = get_le<Unsigned>(content_.data() + at_);
    at_ += sizeof(Unsigned);
    return value;
  }
  ByteView bytes(std::uint64_t size, const char* field) {
    need(size, field);
    const ByteView out = content_.subspan(at_, size);
    at_ += size;
    return out;
  }
  std::string text(const char* field) {
    const ByteView out = bytes(number<std::uint32_t>(field), field);
    return {reinterpret_cast<const char*>(out.data()), out.size()};
  }
  Metadata map(const char* field) {
    Fields entries(bytes(number<std::uint32_t>(field), field), offset_ + at_, record_);
    Metadata out;
    while (!entries.done()) {
      std::string key = entries.text(field);
      out[std::move(key)] = entries.text(field);
    }
    return out;
  }
  ByteView rest() { return bytes(content_.size() - at_, "data"); }
  bool done() const { return at_ == content_.size(); }
  std::uint64_t offset() const { return offset_ + at_; }

 private:
  void need(std::uint64_t size, const char* field) const {
    if (size > content_.size() - at_) {
      fail(offset_ + at_, std::string(record_) + " record too short for its " + field + " (" + std::to_string(size) +
                              " bytes wanted, " + std::to_string(content_.size() - at_) + " left)");
    }
  }

  ByteView content_;
  std::uint64_t offset_;  // of content_[0] in the file
  const char* record_;
  std::uint64_t at_ = 0;
};

struct Record {
  std::uint8_t opcode = 0;
  std::uint64_t offset = 0;  // of its opcode
  ByteView content;
  std::uint64_t end() const { return offset + kRecordHead + content.size(); }
};

// The record at `at` in `bytes` (whose byte 0 is at file offset `base`), or nullopt when
// `bytes` end inside it; `why` says how.
std::optional<Record> record_at(ByteView bytes, std::uint64_t at, std::uint64_t base, std::string& why) {
  if (at == bytes.size()) {
    why = "it ends after a whole record";
    return std::nullopt;
  }
  if (bytes.size() - at < kRecordHead) {
    why = "it ends inside a record's opcode and length";
    return std::nullopt;
  }
  const std::uint8_t opcode = std::to_integer<std::uint8_t>(bytes[at]);
  const std::uint64_t length = get_le<std::uint64_t>(bytes.data() + at + 1);
  if (length > bytes.size() - at - kRecordHead) {
    why = "a record (opcode " + std::to_string(opcode) + ") claims " + std::to_string(length) + " bytes, " +
          std::to_string(bytes.size() - at - kRecordHead) + " follow";
    return std::nullopt;
  }
  return Record{opcode, base + at, bytes.subspan(at + kRecordHead, length)};
}

class FileReader {
 public:
  FileReader(ByteView file, const ReadLimits& limits) : file_(file), limits_(limits) {}

  ReadFile read() {
    if (file_.size() < kMagicSize || !std::equal(kMagic, kMagic + kMagicSize, file_.begin())) {
      fail(0, "not an MCAP file (no MCAP magic)");
    }
    // A file that ends with the magic was finished: nothing in it may be missing. One that
    // does not was cut short, and stops where its last whole record ends.
    whole_ = file_.size() >= 2 * kMagicSize &&
             std::equal(kMagic, kMagic + kMagicSize, file_.end() - static_cast<std::ptrdiff_t>(kMagicSize));
    std::uint64_t at = kMagicSize;
    bool header = false;
    while (true) {
      std::string why;
      const auto record = record_at(file_, at, 0, why);
      if (!record) {
        if (!header) fail(at, "no Header record: " + why);
        if (whole_) fail(at, "no Data End before the file's end: " + why);
        out_.truncated = "byte " + std::to_string(at) + ": the file has no Data End (cut short?): " + why;
        return std::move(out_);
      }
      if (!header) {
        if (record->opcode != kHeader) fail(at, "the first record is not a Header (opcode " + std::to_string(record->opcode) + ")");
        Fields fields(record->content, record->offset + kRecordHead, "Header");
        out_.profile = fields.text("profile");
        out_.library = fields.text("library");
        header = true;
      } else if (record->opcode == kDataEnd) {
        data_end(*record);
        return std::move(out_);
      } else if (record->opcode == kFooter) {
        fail(at, "a Footer before the Data End");
      } else {
        data_record(*record);
      }
      at = record->end();
    }
  }

 private:
  void data_end(const Record& record) {
    Fields fields(record.content, record.offset + kRecordHead, "Data End");
    const std::uint32_t stored = fields.number<std::uint32_t>("data_section_crc");
    const std::uint32_t computed = crc32_update(0, file_.first(record.offset));
    if (stored != 0 && stored != computed) {
      fail(record.offset, "data section CRC " + hex(stored) + " does not match the data (" + hex(computed) + ")");
    }
    summary(record.end());
  }

  // From the summary's start (the Data End's end) to the closing magic.
  void summary(std::uint64_t start) {
    if (!whole_) {
      out_.truncated = "byte " + std::to_string(start) + ": the summary and Footer after the Data End are missing "
                       "or cut short (the file does not end with the MCAP magic)";
      return;
    }
    if (file_.size() - start < kMagicSize + kRecordHead + 20) fail(start, "no Footer after the Data End");
    const std::uint64_t magic_at = file_.size() - kMagicSize;
    const std::uint64_t footer_at = magic_at - kRecordHead - 20;
    if (std::to_integer<std::uint8_t>(file_[footer_at]) != kFooter ||
        get_le<std::uint64_t>(file_.data() + footer_at + 1) != 20) {
      fail(footer_at, "no Footer record before the closing magic");
    }
    Fields footer(file_.subspan(footer_at + kRecordHead, 20), footer_at + kRecordHead, "Footer");
    const std::uint64_t summary_start = footer.number<std::uint64_t>("summary_start");
    const std::uint64_t summary_offset_start = footer.number<std::uint64_t>("summary_offset_start");
    const std::uint32_t stored = footer.number<std::uint32_t>("summary_crc");
    if (summary_start != 0 && (summary_start < start || summary_start > footer_at)) {
      fail(footer_at, "the Footer's summary_start " + std::to_string(summary_start) + " is outside the summary");
    }
    if (summary_offset_start != 0 && (summary_offset_start < start || summary_offset_start > footer_at)) {
      fail(footer_at, "the Footer's summary_offset_start " + std::to_string(summary_offset_start) +
                          " is outside the summary");
    }
    // Every record between the Data End and the Footer must be whole.
    for (std::uint64_t at = start; at < footer_at;) {
      std::string why;
      const auto record = record_at(file_.first(footer_at), at, 0, why);
      if (!record) fail(at, "summary section: " + why);
      at = record->end();
    }
    const std::uint64_t crc_from = summary_start != 0 ? summary_start : footer_at;
    const std::uint32_t computed =
        crc32_update(0, file_.subspan(crc_from, footer_at + kRecordHead + 16 - crc_from));
    if (stored != 0 && stored != computed) {
      fail(footer_at, "summary CRC " + hex(stored) + " does not match the summary (" + hex(computed) + ")");
    }
    out_.complete = true;
  }

  void data_record(const Record& record) {
    switch (record.opcode) {
      case kSchema: return schema(record);
      case kChannel: return channel(record);
      case kMessage: return message(record);
      case kChunk: return chunk(record);
      case kMetadata: return metadata(record);
      case kAttachment: return attachment(record);
      case kHeader: fail(record.offset, "a second Header");
      default: return;  // Message Index, the index records, and opcodes of later versions
    }
  }

  void schema(const Record& record) {
    Fields fields(record.content, record.offset + kRecordHead, "Schema");
    Schema schema;
    schema.id = fields.number<std::uint16_t>("id");
    schema.name = fields.text("name");
    schema.encoding = fields.text("encoding");
    const ByteView data = fields.bytes(fields.number<std::uint32_t>("data"), "data");
    schema.data.assign(data.begin(), data.end());
    if (schema.id == 0) fail(record.offset, "a Schema with id 0");
    out_.schemas.insert_or_assign(schema.id, std::move(schema));
  }

  void channel(const Record& record) {
    Fields fields(record.content, record.offset + kRecordHead, "Channel");
    Channel channel;
    channel.id = fields.number<std::uint16_t>("id");
    channel.schema_id = fields.number<std::uint16_t>("schema_id");
    channel.topic = fields.text("topic");
    channel.message_encoding = fields.text("message_encoding");
    channel.metadata = fields.map("metadata");
    if (channel.schema_id != 0 && out_.schemas.count(channel.schema_id) == 0) {
      fail(record.offset, "Channel " + std::to_string(channel.id) + " names schema " +
                              std::to_string(channel.schema_id) + ", which no Schema record before it has");
    }
    out_.channels.insert_or_assign(channel.id, std::move(channel));
  }

  void message(const Record& record) {
    Fields fields(record.content, record.offset + kRecordHead, "Message");
    ReadMessage message;
    message.channel_id = fields.number<std::uint16_t>("channel_id");
    message.sequence = fields.number<std::uint32_t>("sequence");
    message.log_time = fields.number<std::uint64_t>("log_time");
    message.publish_time = fields.number<std::uint64_t>("publish_time");
    const ByteView data = fields.rest();
    message.data.assign(data.begin(), data.end());
    if (out_.channels.count(message.channel_id) == 0) {
      fail(record.offset, "a Message on channel " + std::to_string(message.channel_id) +
                              ", which no Channel record before it has");
    }
    out_.messages.push_back(std::move(message));
  }

  void metadata(const Record& record) {
    Fields fields(record.content, record.offset + kRecordHead, "Metadata");
    ReadMetadata metadata;
    metadata.name = fields.text("name");
    metadata.metadata = fields.map("metadata");
    out_.metadata.push_back(std::move(metadata));
  }

  void attachment(const Record& record) {
    Fields fields(record.content, record.offset + kRecordHead, "Attachment");
    fields.number<std::uint64_t>("log_time");
    fields.number<std::uint64_t>("create_time");
    fields.text("name");
    fields.text("media_type");
    fields.bytes(fields.number<std::uint64_t>("data"), "data");
    const std::uint64_t crc_at = fields.offset();
    const std::uint32_t stored = fields.number<std::uint32_t>("crc");
    const std::uint32_t computed = crc32_update(0, file_.subspan(record.offset + kRecordHead, crc_at - record.offset - kRecordHead));
    if (stored != 0 && stored != computed) {
      fail(record.offset, "attachment CRC " + hex(stored) + " does not match its content (" + hex(computed) + ")");
    }
  }

  void chunk(const Record& record) {
    Fields fields(record.content, record.offset + kRecordHead, "Chunk");
    fields.number<std::uint64_t>("message_start_time");
    fields.number<std::uint64_t>("message_end_time");
    const std::uint64_t uncompressed_size = fields.number<std::uint64_t>("uncompressed_size");
    const std::uint32_t stored = fields.number<std::uint32_t>("uncompressed_crc");
    const std::string compression = fields.text("compression");
    const std::uint64_t records_at = fields.offset() + 8;
    const ByteView records = fields.bytes(fields.number<std::uint64_t>("records"), "records");
    if (uncompressed_size > limits_.max_uncompressed_bytes - uncompressed_total_) {
      fail(record.offset, "the chunks' records decompress to more than " +
                              std::to_string(limits_.max_uncompressed_bytes) + " bytes (the reader's limit)");
    }
    Bytes inflated;
    ByteView plain = records;
    if (compression == "zstd") {
      inflated = decompress(records, uncompressed_size, record.offset);
      plain = inflated;
    } else if (!compression.empty()) {
      fail(record.offset, "chunk compression \"" + compression.substr(0, 40) +
                              "\" is not supported (only zstd and none)");
    } else if (records.size() != uncompressed_size) {
      fail(record.offset, "an uncompressed chunk of " + std::to_string(records.size()) +
                              " bytes claims uncompressed_size " + std::to_string(uncompressed_size));
    }
    uncompressed_total_ += plain.size();
    const std::uint32_t computed = crc32_update(0, plain);
    if (stored != 0 && stored != computed) {
      fail(record.offset, "chunk CRC " + hex(stored) + " does not match its records (" + hex(computed) + ")");
    }
    // Offsets inside a compressed chunk name no byte of the file: errors there say where the chunk's records start.
    const std::uint64_t base = compression.empty() ? records_at : record.offset;
    for (std::uint64_t at = 0; at < plain.size();) {
      std::string why;
      const auto inner = record_at(plain, at, compression.empty() ? base : 0, why);
      if (!inner) fail(compression.empty() ? base + at : record.offset, "inside a chunk: " + why);
      Record placed = *inner;
      if (!compression.empty()) placed.offset = record.offset;
      switch (placed.opcode) {
        case kSchema: schema(placed); break;
        case kChannel: channel(placed); break;
        case kMessage: message(placed); break;
        default: break;
      }
      at = inner->end() - (compression.empty() ? base : 0);
    }
  }

  Bytes decompress(ByteView records, std::uint64_t uncompressed_size, std::uint64_t offset) {
    const unsigned long long claimed = ZSTD_getFrameContentSize(records.data(), records.size());
    if (claimed == ZSTD_CONTENTSIZE_ERROR) fail(offset, "a zstd chunk whose records are not a zstd frame");
    if (claimed != ZSTD_CONTENTSIZE_UNKNOWN && claimed > uncompressed_size) {
      fail(offset, "a zstd chunk of " + std::to_string(claimed) + " bytes claims uncompressed_size " +
                       std::to_string(uncompressed_size));
    }
    Bytes out(uncompressed_size);
    const std::size_t made = ZSTD_decompress(out.data(), out.size(), records.data(), records.size());
    if (ZSTD_isError(made)) fail(offset, std::string("zstd chunk: ") + ZSTD_getErrorName(made));
    if (made != uncompressed_size) {
      fail(offset, "a zstd chunk decompressed to " + std::to_string(made) + " bytes, not its uncompressed_size " +
                       std::to_string(uncompressed_size));
    }
    return out;
  }

  ByteView file_;
  bool whole_ = false;
  ReadLimits limits_;
  ReadFile out_;
  std::uint64_t uncompressed_total_ = 0;
};

}  // namespace

const Channel* ReadFile::channel_of_topic(std::string_view topic) const {
  for (const auto& [id, channel] : channels) {
    if (channel.topic == topic) return &channel;
  }
  return nullptr;
}

ReadFile read_file(ByteView file, const ReadLimits& limits) { return FileReader(file, limits).read(); }

}  // namespace wheeltec::mcap
