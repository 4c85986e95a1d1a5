#pragma once

// The files wheeltec-web serves over HTTP, read once at start-up so that serving them never
// touches the disk: the page (index.html, app.js, style.css from the page directory) and
// the plotting library from Debian's libjs-dygraphs under /javascript/dygraphs/.

#include <map>
#include <string>
#include <string_view>

namespace wheeltec::web {

struct StaticFile {
  std::string content_type;
  std::string body;
};

class StaticFiles {
 public:
  // Throws std::runtime_error naming the file when one of the page's files is missing; a
  // missing dygraphs is logged (the page then says that its plots need libjs-dygraphs).
  static StaticFiles load(const std::string& page_dir, const std::string& javascript_dir);

  // By URL path; "/" is the page. Null when there is no such file.
  const StaticFile* find(std::string_view path) const;

 private:
  std::map<std::string, StaticFile, std::less<>> files_;
};

}  // namespace wheeltec::web
