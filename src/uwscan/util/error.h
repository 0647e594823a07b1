// Errors: library code throws uwscan::Error through the UWS_CHECK macros; the
// CLI turns it into "uwscan: error: ..." and exit status 1.
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

namespace uwscan {

// Bad input or a runtime failure the user can act on (file, key, value).
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

// A usage error (bad option combination): the CLI exits with status 2.
class UsageError : public Error {
 public:
  explicit UsageError(const std::string& message) : Error(message) {}
};

namespace internal {
template <typename... Args>
std::string Concat(const Args&... args) {
  std::ostringstream out;
  (out << ... << args);
  return out.str();
}
}  // namespace internal

}  // namespace uwscan

// Throws `type` with the streamed message when the condition is false.
#define UWS_CHECK_OR_THROW(type, condition, ...)           \
  do {                                                     \
    if (!(condition)) {                                    \
      throw type(::uwscan::internal::Concat(__VA_ARGS__)); \
    }                                                      \
  } while (false)

// Throws uwscan::Error with the streamed message when the condition is false.
#define UWS_CHECK(condition, ...) UWS_CHECK_OR_THROW(::uwscan::Error, condition, __VA_ARGS__)

#define UWS_THROW(...) throw ::uwscan::Error(::uwscan::internal::Concat(__VA_ARGS__))

// The same for what the command line set: uwscan::UsageError (exit status 2).
#define UWS_USAGE_CHECK(condition, ...) \
  UWS_CHECK_OR_THROW(::uwscan::UsageError, condition, __VA_ARGS__)
