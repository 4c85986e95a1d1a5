#pragma once

// A Beast body that is a part of an open file: `size` bytes from `offset` (the whole file, or
// one range of a Range request), read 4 KiB at a time when the serializer asks, as Beast's
// file_body does for whole files (Boost 1.74's has no ranges).

#include <array>
#include <cstdint>
#include <utility>

#include <boost/asio/buffer.hpp>
#include <boost/beast/core/error.hpp>
#include <boost/beast/core/file.hpp>
#include <boost/beast/http/message.hpp>
#include <boost/optional.hpp>

namespace wheeltec::web {

struct FileRangeBody {
  struct value_type {
    boost::beast::file file;
    std::uint64_t offset = 0;
    std::uint64_t size = 0;
  };

  static std::uint64_t size(const value_type& body) { return body.size; }

  class writer {
   public:
    using const_buffers_type = boost::asio::const_buffer;

    template <bool isRequest, class Fields>
    writer(boost::beast::http::header<isRequest, Fields>&, value_type& body) : body_(body), remain_(body.size) {}

    void init(boost::beast::error_code& ec) { body_.file.seek(body_.offset, ec); }

    boost::optional<std::pair<const_buffers_type, bool>> get(boost::beast::error_code& ec) {
      const std::size_t amount = remain_ > buffer_.size() ? buffer_.size() : static_cast<std::size_t>(remain_);
      if (amount == 0) {
        ec = {};
        return boost::none;
      }
      const std::size_t read = body_.file.read(buffer_.data(), amount, ec);
      if (ec) return boost::none;
      if (read == 0) {  // the file shrank under us
        ec = boost::beast::errc::make_error_code(boost::beast::errc::io_error);
        return boost::none;
      }
      remain_ -= read;
      return {{const_buffers_type(buffer_.data(), read), remain_ > 0}};
    }

   private:
    value_type& body_;
    std::uint64_t remain_;
    std::array<char, 4096> buffer_{};
  };
};

}  // namespace wheeltec::web
