// Errors cross houle's library boundary as values, never as exceptions: a function that can fail
// returns Expected<T> (a T or an Error), or Expected<void> (success or an Error) when it has nothing
// else to return. Both are [[nodiscard]]: a result ignored on purpose is cast to void with a comment
// saying why. The accessors never throw: asking for the value of an error (or the error of a success)
// breaks the contract, which HOULE_ASSERT checks in debug builds (assert.hpp).
#pragma once
#include <cstdlib>
#include <optional>
#include <string>
#include <utility>
#include <variant>

#include "houle/runtime/assert.hpp"

namespace houle {

/// What went wrong, for a person: `field` names the offending input ("trains[2].amplitude"),
/// `message` says what was expected.
struct Error {
  std::string field;
  std::string message;
};

namespace detail {
/// What an Expected's accessor returns, checked: the value of an Error (or the error of a success)
/// breaks the contract. HOULE_ASSERT says where in debug builds; a release build stops as well
/// instead of reading through the null pointer (std::get would have thrown).
template <class P>
P* expected_present(P* p, const char* what) noexcept {
  HOULE_ASSERT(p != nullptr, what);
  if (p == nullptr) std::abort();
  return p;
}
inline constexpr const char* expected_no_value = "the value of an Expected that holds an Error";
inline constexpr const char* expected_no_error = "the error of an Expected that holds no Error";
}  // namespace detail

/// A T or the Error that prevented it. value(), * and -> need ok(); error() needs !ok().
template <class T>
class [[nodiscard]] Expected {
 public:
  Expected(T value) : v_(std::in_place_index<0>, std::move(value)) {}      // NOLINT(google-explicit-constructor)
  Expected(Error error) : v_(std::in_place_index<1>, std::move(error)) {}  // NOLINT(google-explicit-constructor)
  bool ok() const noexcept { return v_.index() == 0; }
  explicit operator bool() const noexcept { return ok(); }
  T& value() & noexcept { return *held(); }
  const T& value() const& noexcept { return *held(); }
  T&& value() && noexcept { return std::move(*held()); }
  const Error& error() const noexcept { return *detail::expected_present(std::get_if<1>(&v_), detail::expected_no_error); }
  T& operator*() & noexcept { return *held(); }
  const T& operator*() const& noexcept { return *held(); }
  T* operator->() noexcept { return held(); }
  const T* operator->() const noexcept { return held(); }

 private:
  T* held() noexcept { return detail::expected_present(std::get_if<0>(&v_), detail::expected_no_value); }
  const T* held() const noexcept { return detail::expected_present(std::get_if<0>(&v_), detail::expected_no_value); }
  std::variant<T, Error> v_;
};

/// Success, or the Error that prevented it: `return {};` succeeds.
template <>
class [[nodiscard]] Expected<void> {
 public:
  Expected() noexcept = default;
  Expected(Error error) : error_(std::move(error)) {}  // NOLINT(google-explicit-constructor)
  bool ok() const noexcept { return !error_.has_value(); }
  explicit operator bool() const noexcept { return ok(); }
  const Error& error() const noexcept {
    return *detail::expected_present(error_ ? &*error_ : nullptr, detail::expected_no_error);
  }

 private:
  std::optional<Error> error_;
};

}  // namespace houle
