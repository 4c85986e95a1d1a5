#include "zstd_compressor.hpp"

#include <zstd.h>

#include <new>
#include <string>

namespace wheeltec::mcap {

void ZstdCompressor::FreeContext::operator()(ZSTD_CCtx_s* context) const { ZSTD_freeCCtx(context); }

ZstdCompressor::ZstdCompressor(int level) : level_(level), context_(ZSTD_createCCtx()) {
  if (level < 1 || level > 19) throw Error("zstd compression level " + std::to_string(level) + " is not 1 to 19");
  if (!context_) throw std::bad_alloc();
}

ZstdCompressor::~ZstdCompressor() = default;

Bytes ZstdCompressor::compress(ByteView input) {
  scratch_.resize(ZSTD_compressBound(input.size()));
  const std::size_t size =
      ZSTD_compressCCtx(context_.get(), scratch_.data(), scratch_.size(), input.data(), input.size(), level_);
  if (ZSTD_isError(size) != 0) throw Error(std::string("zstd: ") + ZSTD_getErrorName(size));
  return Bytes(scratch_.begin(), scratch_.begin() + static_cast<std::ptrdiff_t>(size));
}

}  // namespace wheeltec::mcap
