#pragma once

// An HTTP response whose body is a file or a part of one, written in pieces (file_range_body.hpp
// reads 4 KiB at a time) so that a file of hundreds of MB never sits in memory and the one Asio thread
// serves other connections between two pieces. Each piece has its own deadline: a client
// that takes nothing for `stall` is cut off, one that keeps reading may take as long as it
// needs.

#include <chrono>
#include <functional>
#include <memory>

#include <boost/beast/http/message.hpp>

#include "file_range_body.hpp"
#include "web_stream.hpp"

namespace wheeltec::web {

using FileResponse = boost::beast::http::response<FileRangeBody>;

// Writes `response` on `stream`; `done` gets the first error, or none once all is written.
// The caller keeps `stream` alive until then.
void async_write_file_response(WebStream& stream, std::shared_ptr<FileResponse> response,
                               std::chrono::steady_clock::duration stall,
                               std::function<void(boost::beast::error_code)> done);

}  // namespace wheeltec::web
