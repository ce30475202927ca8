// Span<T>: a view, convertible to const, with sub-views that alias the same memory.
#include <gtest/gtest.h>

#include <type_traits>
#include <vector>

#include "kernels/core/span.h"

namespace romp {
namespace {

static_assert(std::is_convertible_v<Span<float>, Span<const float>>);
static_assert(!std::is_convertible_v<Span<const float>, Span<float>>, "a const view never becomes mutable");

TEST(Span, ViewsAndSubviewsAliasTheSameMemory) {
  std::vector<int> values{0, 1, 2, 3, 4, 5};
  const Span<int> all(values.data(), Index(values.size()));
  const Span<int> middle = all.subspan(2, 3);
  EXPECT_EQ(middle.size(), 3);
  EXPECT_EQ(middle[0], 2);
  middle[2] = 40;
  EXPECT_EQ(values[4], 40);
  const Span<const int> read_only = all;
  EXPECT_EQ(read_only.data(), values.data());
  int sum = 0;
  for (int v : read_only) sum += v;
  EXPECT_EQ(sum, 0 + 1 + 2 + 3 + 40 + 5);
}

TEST(Span, DefaultIsEmpty) {
  const Span<double> empty;
  EXPECT_TRUE(empty.empty());
  EXPECT_EQ(empty.data(), nullptr);
}

}  // namespace
}  // namespace romp
