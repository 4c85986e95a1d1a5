#include "file_response.hpp"

#include <boost/beast/http/serializer.hpp>
#include <boost/beast/http/write.hpp>

namespace wheeltec::web {
namespace {

namespace http = boost::beast::http;

struct PieceWriter : std::enable_shared_from_this<PieceWriter> {
  PieceWriter(WebStream& stream, std::shared_ptr<FileResponse> response, std::chrono::steady_clock::duration stall,
              std::function<void(boost::beast::error_code)> done)
      : stream(stream), response(std::move(response)), serializer(*this->response), stall(stall),
        done(std::move(done)) {}

  void next() {
    stream.tcp().expires_after(stall);
    http::async_write_some(stream, serializer,
                           [self = shared_from_this()](boost::beast::error_code ec, std::size_t) {
                             if (ec || self->serializer.is_done()) return self->done(ec);
                             self->next();
                           });
  }

  WebStream& stream;
  std::shared_ptr<FileResponse> response;
  http::response_serializer<FileRangeBody> serializer;
  std::chrono::steady_clock::duration stall;
  std::function<void(boost::beast::error_code)> done;
};

}  // namespace

void async_write_file_response(WebStream& stream, std::shared_ptr<FileResponse> response,
                               std::chrono::steady_clock::duration stall,
                               std::function<void(boost::beast::error_code)> done) {
  std::make_shared<PieceWriter>(stream, std::move(response), stall, std::move(done))->next();
}

}  // namespace wheeltec::web
