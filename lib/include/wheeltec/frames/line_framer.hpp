#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace wheeltec {

// Splits a byte stream into '\n'-terminated lines, no longer than a maximum. When the
// stream has ended, an unterminated rest is its last line.
//
// The buffer holds the unread lines and the bytes of one more append(): the reader
// appends only when next() says incomplete, and then at most max_line_bytes are pending.
class LineFramer {
 public:
  enum class Next {
    line,        // line() is a complete line
    incomplete,  // more input is needed
    too_long,    // the first pending line is longer than max_line_bytes
    end,         // the stream ended and every line was taken
  };

  explicit LineFramer(std::size_t max_line_bytes);

  void append(std::string_view bytes);
  // The stream has ended: no more append().
  void finish() { finished_ = true; }
  bool finished() const { return finished_; }

  // What comes next; does not take it.
  Next next() const;
  // When next() is line: the line, without its '\n'. Valid until the next append() or discard().
  std::string_view line() const;
  // When next() is line: moves past it.
  void pop();

  // Drops every pending byte and releases the buffer; finished() stays as it is.
  void discard();

 private:
  std::size_t max_line_bytes_;
  std::string buffer_;
  std::size_t begin_ = 0;                     // start of the first pending line
  std::size_t newline_ = std::string::npos;  // its '\n', npos if not received yet
  bool finished_ = false;
};

}  // namespace wheeltec
