#include "directory_store.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>

#include <fmt/format.h>

#include "wheeltec/config/config_document.hpp"

#include "wheeltec/record/file_names.hpp"

namespace wheeltec::record {
namespace {

[[noreturn]] void throw_errno(const std::string& what) {
  throw std::system_error(errno, std::generic_category(), what);
}

void sync_directory(const std::filesystem::path& directory) {
  const int fd = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) throw_errno(directory.string());
  const int synced = ::fsync(fd);
  const int sync_errno = errno;
  ::close(fd);
  if (synced != 0) throw std::system_error(sync_errno, std::generic_category(), directory.string());
}

class DirectoryFile : public FileOutput {
 public:
  DirectoryFile(std::filesystem::path directory, std::string name)
      : directory_(std::move(directory)),
        name_(std::move(name)),
        part_(directory_ / part_name(name_)),
        fd_(::open(part_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0640)) {
    if (fd_ < 0) throw_errno(part_.string());
  }
  ~DirectoryFile() override { ::close(fd_); }
  DirectoryFile(const DirectoryFile&) = delete;
  DirectoryFile& operator=(const DirectoryFile&) = delete;

  void write(mcap::ByteView bytes) override {
    const auto* data = reinterpret_cast<const char*>(bytes.data());
    std::size_t left = bytes.size();
    while (left > 0) {
      const ssize_t written = ::write(fd_, data, left);
      if (written < 0 && errno == EINTR) continue;
      if (written < 0) throw_errno(part_.string());
      data += written;
      left -= static_cast<std::size_t>(written);
    }
  }

  void commit() override {
    if (::fsync(fd_) != 0) throw_errno(part_.string());
    const std::filesystem::path whole = directory_ / name_;
    if (::rename(part_.c_str(), whole.c_str()) != 0) throw_errno(whole.string());
    sync_directory(directory_);
  }

 private:
  std::filesystem::path directory_;
  std::string name_;
  std::filesystem::path part_;
  int fd_;
};

}  // namespace

std::unique_ptr<FileOutput> DirectoryStore::create(const std::string& name) {
  return std::make_unique<DirectoryFile>(directory_, name);
}

std::vector<StoredFile> DirectoryStore::list() const {
  std::vector<StoredFile> files;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(directory_, error)) {
    std::error_code size_error;
    if (!entry.is_regular_file(size_error)) continue;
    const auto bytes = entry.file_size(size_error);
    if (size_error) continue;  // removed meanwhile
    files.push_back(StoredFile{entry.path().filename().string(), bytes});
  }
  if (error) throw std::system_error(error, directory_.string());
  return files;
}

void DirectoryStore::remove(const std::string& name) {
  const std::filesystem::path path = directory_ / name;
  if (::unlink(path.c_str()) != 0 && errno != ENOENT) throw_errno(path.string());
}

void prepare_directory(const std::filesystem::path& directory) {
  std::error_code error;
  std::filesystem::create_directories(directory, error);
  if (error) {
    throw ConfigError("dir", fmt::format("cannot create {}: {}", directory.string(), error.message()));
  }
  const std::filesystem::path probe = directory / ".wheeltec-record-probe";
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  const int open_errno = errno;
  if (fd < 0) {
    throw ConfigError("dir", fmt::format("cannot write in {}: {}", directory.string(),
                                         std::generic_category().message(open_errno)));
  }
  ::close(fd);
  ::unlink(probe.c_str());
}

}  // namespace wheeltec::record
