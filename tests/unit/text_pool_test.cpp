#include "wheeltec/api/text_pool.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

namespace {

using wheeltec::TextPool;

TEST(TextPool, GivesAnEmptyStringWithTheReservedCapacity) {
  TextPool pool(768);
  const auto text = pool.acquire();
  EXPECT_TRUE(text->empty());
  EXPECT_GE(text->capacity(), 768u);
}

TEST(TextPool, ReusesAStringOnceNobodyHoldsIt) {
  TextPool pool(64);
  const std::string* first = nullptr;
  {
    auto text = pool.acquire();
    *text = "a notification";
    first = text.get();
    const std::shared_ptr<const std::string> queued = text;  // as a session queues it
  }
  const auto again = pool.acquire();
  EXPECT_EQ(again.get(), first);
  EXPECT_TRUE(again->empty());
}

TEST(TextPool, NeverHandsOutAStringThatIsStillQueued) {
  TextPool pool(64);
  std::vector<std::shared_ptr<const std::string>> queued;
  for (std::size_t i = 0; i < 3 * TextPool::capacity; ++i) {
    auto text = pool.acquire();
    for (const auto& held : queued) ASSERT_NE(held.get(), text.get());
    *text = std::to_string(i);
    queued.push_back(text);
  }
  for (std::size_t i = 0; i < queued.size(); ++i) EXPECT_EQ(*queued[i], std::to_string(i));
}

}  // namespace
