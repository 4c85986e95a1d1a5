#pragma once

// The recorder's FileStore on a directory (--dir): each file is written through its own
// descriptor, fsync'd, then renamed, and the directory fsync'd, so that after a power cut
// a file under its final name is whole.

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "file_store.hpp"

namespace wheeltec::record {

class DirectoryStore : public FileStore {
 public:
  explicit DirectoryStore(std::filesystem::path directory) : directory_(std::move(directory)) {}

  std::unique_ptr<FileOutput> create(const std::string& name) override;
  std::vector<StoredFile> list() const override;
  void remove(const std::string& name) override;

  const std::filesystem::path& directory() const { return directory_; }

 private:
  std::filesystem::path directory_;
};

// Creates `directory` (and its parents) when missing, and checks that a file can be created
// and written in it; throws ConfigError on key "dir" naming it and the cause.
void prepare_directory(const std::filesystem::path& directory);

}  // namespace wheeltec::record
