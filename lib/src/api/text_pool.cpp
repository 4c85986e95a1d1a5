#include "wheeltec/api/text_pool.hpp"

namespace wheeltec {

std::shared_ptr<std::string> TextPool::acquire() {
  for (auto& text : pool_) {
    if (!text) {
      text = fresh();
      return text;
    }
    if (text.use_count() == 1) {  // only the pool holds it: every session has let it go
      text->clear();
      return text;
    }
  }
  return fresh();
}

std::shared_ptr<std::string> TextPool::fresh() const {
  auto text = std::make_shared<std::string>();
  text->reserve(reserve_bytes_);
  return text;
}

}  // namespace wheeltec
