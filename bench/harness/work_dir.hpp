#pragma once

#include <filesystem>
#include <string>

namespace bench {

// Where a benchmark keeps its programs' files: the directory given (created, kept), or a new
// one in the temporary directory, removed with everything in it at the end.
class WorkDir {
 public:
  WorkDir(const std::string& name, const std::string& given = {});
  ~WorkDir();
  WorkDir(const WorkDir&) = delete;
  WorkDir& operator=(const WorkDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  bool keep_;
};

}  // namespace bench
