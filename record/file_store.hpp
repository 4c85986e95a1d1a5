#pragma once

// Where the recorder's files go: created under NAME.part, renamed to NAME when whole
// (spec section 10). An interface, so that the black box runs against a directory in
// wheeltec-record and against memory in its tests.

#include <memory>
#include <string>
#include <vector>

#include "wheeltec/mcap/types.hpp"

#include "retention.hpp"  // StoredFile

namespace wheeltec::record {

// A file being written. Destroyed before commit(), it stays under its .part name, as
// after a crash.
class FileOutput {
 public:
  virtual ~FileOutput() = default;
  // Throws std::system_error (a full disk, a removed directory).
  virtual void write(mcap::ByteView bytes) = 0;
  // Makes the bytes durable and renames NAME.part to NAME. Throws std::system_error.
  virtual void commit() = 0;
};

class FileStore {
 public:
  virtual ~FileStore() = default;
  // A new file to be named `name` when committed, written as `name` + ".part" meanwhile.
  // Throws std::system_error.
  virtual std::unique_ptr<FileOutput> create(const std::string& name) = 0;
  // The files there now, .part ones included. Throws std::system_error.
  virtual std::vector<StoredFile> list() const = 0;
  // Throws std::system_error.
  virtual void remove(const std::string& name) = 0;
};

}  // namespace wheeltec::record
