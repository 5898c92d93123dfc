// Expected<T> and Expected<void> (houle/runtime/expected.hpp): values, errors, moves, and move-only T.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <utility>

#include "houle/runtime/expected.hpp"

namespace {

using houle::Error;
using houle::Expected;

Expected<int> half(int n) {
  if (n % 2 != 0) return Error{"n", "an even number, got " + std::to_string(n)};
  return n / 2;
}

Expected<void> even(int n) {
  if (n % 2 != 0) return Error{"n", "an even number"};
  return {};
}

TEST(Expected, HoldsTheValue) {
  Expected<int> e = half(8);
  ASSERT_TRUE(e.ok());
  EXPECT_TRUE(bool(e));
  EXPECT_EQ(e.value(), 4);
  EXPECT_EQ(*e, 4);
  e.value() = 5;
  EXPECT_EQ(std::as_const(e).value(), 5);
}

TEST(Expected, HoldsTheError) {
  const Expected<int> e = half(7);
  ASSERT_FALSE(e.ok());
  EXPECT_FALSE(bool(e));
  EXPECT_EQ(e.error().field, "n");
  EXPECT_EQ(e.error().message, "an even number, got 7");
}

TEST(Expected, ArrowReachesMembersOfTheValue) {
  Expected<std::string> e = std::string("surface");
  EXPECT_EQ(e->size(), 7u);
  e->append(".levels");
  EXPECT_EQ(*e, "surface.levels");
}

TEST(Expected, PassesAnErrorOnAsAnotherType) {
  const auto twice_half = [](int n) -> Expected<long> {
    const Expected<int> h = half(n);
    if (!h) return h.error();
    return 2L * h.value();
  };
  EXPECT_EQ(twice_half(6).value(), 6L);
  EXPECT_EQ(twice_half(3).error().message, "an even number, got 3");
}

TEST(Expected, MoveOnlyValues) {
  Expected<std::unique_ptr<int>> e = std::make_unique<int>(42);
  ASSERT_TRUE(e.ok());
  EXPECT_EQ(*e.value(), 42);
  Expected<std::unique_ptr<int>> moved = std::move(e);
  ASSERT_TRUE(moved.ok());
  const std::unique_ptr<int> p = std::move(moved).value();
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(*p, 42);

  const Expected<std::unique_ptr<int>> failed = Error{"threads", "could not start a worker thread"};
  ASSERT_FALSE(failed.ok());
  EXPECT_EQ(failed.error().field, "threads");
}

TEST(Expected, ReassignsBetweenValueAndError) {
  Expected<std::string> e = Error{"", ""};
  EXPECT_FALSE(e.ok());
  e = std::string("traced");
  ASSERT_TRUE(e.ok());
  EXPECT_EQ(e.value(), "traced");
  e = Error{"scene", "too large"};
  ASSERT_FALSE(e.ok());
  EXPECT_EQ(e.error().message, "too large");
}

TEST(ExpectedVoid, SucceedsWithNothing) {
  const Expected<void> e = even(4);
  EXPECT_TRUE(e.ok());
  EXPECT_TRUE(bool(e));
  const Expected<void> made{};
  EXPECT_TRUE(made.ok());
}

TEST(ExpectedVoid, HoldsTheError) {
  const Expected<void> e = even(3);
  ASSERT_FALSE(e.ok());
  EXPECT_FALSE(bool(e));
  EXPECT_EQ(e.error().field, "n");
  EXPECT_EQ(e.error().message, "an even number");
  // Copies and moves keep the error.
  Expected<void> copy = e;
  ASSERT_FALSE(copy.ok());
  const Expected<void> moved = std::move(copy);
  ASSERT_FALSE(moved.ok());
  EXPECT_EQ(moved.error().field, "n");
}

TEST(ExpectedVoid, PassesItsErrorOnToAValuedExpected) {
  const auto checked_half = [](int n) -> Expected<int> {
    if (const Expected<void> ok = even(n); !ok) return ok.error();
    return n / 2;
  };
  EXPECT_EQ(checked_half(10).value(), 5);
  EXPECT_EQ(checked_half(9).error().message, "an even number");
}

}  // namespace
