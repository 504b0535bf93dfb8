#pragma once

#include <string>
#include <utility>

namespace rov_tether
{

/// Outcome of a call that can refuse its input; the message says why (or, on success, what was done).
/// [[nodiscard]]: a caller that drops a refusal gets a compiler warning (docs/architecture.md, Errors).
struct [[nodiscard]] Status
{
  bool ok = true;
  std::string message;

  static Status success() { return {}; }
  static Status error(std::string text) { return {false, std::move(text)}; }
  explicit operator bool() const { return ok; }
};

}  // namespace rov_tether
