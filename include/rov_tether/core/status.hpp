#pragma once

#include <string>
#include <utility>
#include <vector>

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

/// The messages one after the other, `separator` between two ("" for none): how a reader lists every problem
/// it found in one error.
inline std::string joinMessages(const std::vector<std::string>& messages, const char* separator = "; ")
{
  std::string text;
  for (const auto& message : messages)
  {
    text += (text.empty() ? "" : separator) + message;
  }
  return text;
}

}  // namespace rov_tether
