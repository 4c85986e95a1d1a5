#include "static_files.hpp"

#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>

#include <spdlog/spdlog.h>

namespace wheeltec::web {
namespace {

std::optional<std::string> read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string content_type_of(std::string_view name) {
  const auto ends_with = [&](std::string_view suffix) {
    return name.size() >= suffix.size() && name.substr(name.size() - suffix.size()) == suffix;
  };
  if (ends_with(".html")) return "text/html; charset=utf-8";
  if (ends_with(".js")) return "text/javascript; charset=utf-8";
  if (ends_with(".css")) return "text/css; charset=utf-8";
  return "application/octet-stream";
}

}  // namespace

StaticFiles StaticFiles::load(const std::string& page_dir, const std::string& javascript_dir) {
  StaticFiles files;
  for (const char* name : {"index.html", "app.js", "style.css"}) {
    const std::string path = page_dir + "/" + name;
    auto body = read_file(path);
    if (!body) throw std::runtime_error("cannot read the page's file " + path);
    files.files_["/" + std::string(name)] = {content_type_of(name), std::move(*body)};
  }
  files.files_["/"] = files.files_["/index.html"];
  for (const char* name : {"dygraphs/dygraph.min.js", "dygraphs/dygraph.min.css"}) {
    const std::string path = javascript_dir + "/" + name;
    if (auto body = read_file(path)) {
      files.files_["/javascript/" + std::string(name)] = {content_type_of(name), std::move(*body)};
    } else {
      spdlog::warn("cannot read {} (Debian package libjs-dygraphs): the page will show no plots", path);
    }
  }
  return files;
}

const StaticFile* StaticFiles::find(std::string_view path) const {
  const auto found = files_.find(path);
  return found == files_.end() ? nullptr : &found->second;
}

}  // namespace wheeltec::web
