// Errors cross houle's library boundary as values, never as exceptions.
#pragma once
#include <string>
#include <utility>
#include <variant>

namespace houle {

/// What went wrong, for a person: `field` names the offending input ("trains[2].amplitude"),
/// `message` says what was expected.
struct Error {
  std::string field;
  std::string message;
};

/// A T or the Error that prevented it.
template <class T>
class Expected {
 public:
  Expected(T value) : v_(std::move(value)) {}                 // NOLINT(google-explicit-constructor)
  Expected(Error error) : v_(std::move(error)) {}             // NOLINT(google-explicit-constructor)
  bool ok() const noexcept { return v_.index() == 0; }
  explicit operator bool() const noexcept { return ok(); }
  T& value() & { return std::get<0>(v_); }
  const T& value() const& { return std::get<0>(v_); }
  T&& value() && { return std::get<0>(std::move(v_)); }
  const Error& error() const { return std::get<1>(v_); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }

 private:
  std::variant<T, Error> v_;
};

}  // namespace houle
