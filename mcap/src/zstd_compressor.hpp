#pragma once

#include <memory>

#include "wheeltec/mcap/types.hpp"

struct ZSTD_CCtx_s;

namespace wheeltec::mcap {

// zstd at one level, with one compression context kept between chunks.
class ZstdCompressor {
 public:
  // Throws Error for a level outside 1 to 19 (zstd's own; 20 to 22 need far more memory).
  explicit ZstdCompressor(int level);
  ~ZstdCompressor();

  // One zstd frame, with the input's size in its header; exactly as large as it is.
  Bytes compress(ByteView input);

 private:
  struct FreeContext {
    void operator()(ZSTD_CCtx_s* context) const;
  };

  int level_;
  std::unique_ptr<ZSTD_CCtx_s, FreeContext> context_;
  Bytes scratch_;
};

}  // namespace wheeltec::mcap
