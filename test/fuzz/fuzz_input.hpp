#pragma once
// Reads typed values from a fuzzer's byte string (zeros once it runs out).

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

namespace rov_tether::fuzz
{

class Input
{
 public:
  Input(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  bool empty() const { return offset_ >= size_; }
  std::uint8_t byte() { return offset_ < size_ ? data_[offset_++] : 0; }
  /// Any double, NaN, infinities and denormals included.
  double rawDouble()
  {
    std::uint64_t bits = 0;
    for (int i = 0; i < 8; ++i)
    {
      bits = (bits << 8) | byte();
    }
    double value;
    std::memcpy(&value, &bits, sizeof(value));
    return value;
  }
  /// Mostly sane doubles in [-scale, scale], sometimes raw ones (NaN, inf, huge).
  double number(double scale)
  {
    const std::uint8_t kind = byte();
    if (kind < 16)
    {
      return rawDouble();
    }
    const std::uint16_t fraction = static_cast<std::uint16_t>(byte() << 8 | byte());
    return scale * (static_cast<double>(fraction) / 32767.5 - 1.0);
  }
  std::string text(std::size_t max_length)
  {
    std::string out;
    const std::size_t length = byte() % (max_length + 1);
    for (std::size_t i = 0; i < length && !empty(); ++i)
    {
      out.push_back(static_cast<char>(byte()));
    }
    return out;
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t offset_ = 0;
};

}  // namespace rov_tether::fuzz
