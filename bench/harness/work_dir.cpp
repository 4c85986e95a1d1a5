#include "work_dir.hpp"

#include <stdlib.h>

#include <stdexcept>

namespace bench {

WorkDir::WorkDir(const std::string& name, const std::string& given) : path_(given), keep_(!given.empty()) {
  if (keep_) {
    std::filesystem::create_directories(path_);
    return;
  }
  std::string pattern = (std::filesystem::temp_directory_path() / (name + ".XXXXXX")).string();
  if (::mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
  path_ = pattern;
}

WorkDir::~WorkDir() {
  std::error_code ignored;
  if (!keep_) std::filesystem::remove_all(path_, ignored);
}

}  // namespace bench
