#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <string>

namespace wheeltec {

// Strings handed to the client sessions that queue them (as SharedText), taken back once
// no session holds one any more: while the subscribers keep up, building a notification
// for every record allocates nothing. When every pooled string is still queued somewhere
// (slow subscribers), a fresh one is made and not kept.
class TextPool {
 public:
  static constexpr std::size_t capacity = 8;

  explicit TextPool(std::size_t reserve_bytes) : reserve_bytes_(reserve_bytes) {}

  // An empty string, with at least reserve_bytes of capacity, that nobody else holds.
  std::shared_ptr<std::string> acquire();

 private:
  std::shared_ptr<std::string> fresh() const;

  std::size_t reserve_bytes_;
  std::array<std::shared_ptr<std::string>, capacity> pool_;
};

}  // namespace wheeltec
