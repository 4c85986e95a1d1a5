#include "wheeltec/frames/line_framer.hpp"

namespace wheeltec {

LineFramer::LineFramer(std::size_t max_line_bytes) : max_line_bytes_(max_line_bytes) {}

void LineFramer::append(std::string_view bytes) {
  if (begin_ > 0) {
    buffer_.erase(0, begin_);
    if (newline_ != std::string::npos) newline_ -= begin_;
    begin_ = 0;
  }
  const std::size_t searched = buffer_.size();
  buffer_.append(bytes);
  if (newline_ == std::string::npos) newline_ = buffer_.find('\n', searched);
}

LineFramer::Next LineFramer::next() const {
  const std::size_t line_end = newline_ == std::string::npos ? buffer_.size() : newline_;
  if (line_end - begin_ > max_line_bytes_) return Next::too_long;
  if (newline_ != std::string::npos) return Next::line;
  if (!finished_) return Next::incomplete;
  return begin_ < buffer_.size() ? Next::line : Next::end;
}

std::string_view LineFramer::line() const {
  const std::size_t line_end = newline_ == std::string::npos ? buffer_.size() : newline_;
  return std::string_view(buffer_).substr(begin_, line_end - begin_);
}

void LineFramer::pop() {
  if (newline_ == std::string::npos) {
    begin_ = buffer_.size();  // the unterminated last line of a finished stream
    return;
  }
  begin_ = newline_ + 1;
  newline_ = buffer_.find('\n', begin_);
}

void LineFramer::discard() {
  buffer_.clear();
  buffer_.shrink_to_fit();
  begin_ = 0;
  newline_ = std::string::npos;
}

}  // namespace wheeltec
