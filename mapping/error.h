// Errors as values: every fallible texbake function returns Expected<T>.
// std::expected is C++23; this is the small subset texbake needs.
#pragma once

#include <cassert>
#include <string>
#include <utility>
#include <variant>

namespace texbake {

enum class ErrorCode {
  kInvalidArgument,  // bad user value (flag, JSON value, geometry): CLI exit 2 for flags
  kParse,            // a file's content is wrong (bad header, NaN, bad index): exit 1
  kIo,               // a file cannot be opened, read or written: exit 1
  kUnsupported,      // a valid request texbake cannot do (e.g. PLY with an atlas): exit 2
  kInternal,         // a library failed unexpectedly: exit 1
  kCancelled,        // a progress callback asked to stop (texbake/texbake.h): exit 1
};

struct Error {
  ErrorCode code = ErrorCode::kInternal;
  std::string message;  // human readable, names the file, line, flag or key
};

inline Error make_error(ErrorCode code, std::string message) {
  return Error{code, std::move(message)};
}

template <class T>
class [[nodiscard]] Expected {
 public:
  Expected(T value) : v_(std::move(value)) {}
  Expected(Error error) : v_(std::move(error)) {}

  bool has_value() const { return v_.index() == 0; }
  explicit operator bool() const { return has_value(); }

  T& value() & {
    assert(has_value());
    return std::get<0>(v_);
  }
  const T& value() const& {
    assert(has_value());
    return std::get<0>(v_);
  }
  T&& value() && {
    assert(has_value());
    return std::get<0>(std::move(v_));
  }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }

  const Error& error() const {
    assert(!has_value());
    return std::get<1>(v_);
  }

 private:
  std::variant<T, Error> v_;
};

// Expected<void>: success or an Error.
struct Ok {};
using Status = Expected<Ok>;
inline Status ok_status() {
  return Ok{};
}

}  // namespace texbake
