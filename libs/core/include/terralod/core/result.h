#pragma once
// Result types for operations that can fail on bad data (files, network, user input).
// Habit: assert on misuse, return on bad data. A failed Result carries one human-readable
// line that names the file or value and the problem; callers add context, never rethrow.

#include <cassert>
#include <string>
#include <utility>
#include <variant>

namespace terralod {

/// One line describing what went wrong, e.g. "dem.tif: truncated GeoTIFF (tile 3 unreadable)".
struct Error {
  std::string message;
};

/// Either a value or an Error. Cheap to move; checking ok() before value() is mandatory.
template <typename T>
class [[nodiscard]] Result {
 public:
  Result(T value) : mState(std::in_place_index<0>, std::move(value)) {}
  Result(Error error) : mState(std::in_place_index<1>, std::move(error)) {}

  bool ok() const { return mState.index() == 0; }
  explicit operator bool() const { return ok(); }

  T& value() & {
    assert(ok());
    return std::get<0>(mState);
  }
  const T& value() const& {
    assert(ok());
    return std::get<0>(mState);
  }
  T&& value() && {
    assert(ok());
    return std::get<0>(std::move(mState));
  }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }

  const Error& error() const {
    assert(!ok());
    return std::get<1>(mState);
  }

 private:
  std::variant<T, Error> mState;
};

/// Result of an operation that produces nothing but can fail.
template <>
class [[nodiscard]] Result<void> {
 public:
  Result() = default;
  Result(Error error) : mError(std::move(error)), mFailed(true) {}

  bool ok() const { return !mFailed; }
  explicit operator bool() const { return ok(); }
  const Error& error() const {
    assert(mFailed);
    return mError;
  }

 private:
  Error mError;
  bool mFailed = false;
};

using Status = Result<void>;

/// Builds an Error from a subject (usually a path) and a problem: "subject: problem".
inline Error makeError(const std::string& subject, const std::string& problem) {
  return Error{subject.empty() ? problem : subject + ": " + problem};
}

}  // namespace terralod
