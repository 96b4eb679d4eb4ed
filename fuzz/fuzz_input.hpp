#pragma once
// Structured values drawn from a fuzz input, for targets that build their
// test case (a log to damage, a device's behaviour, a chunking) from the
// bytes rather than parsing them directly. An exhausted input reads as
// zeros, so every input is a valid case.
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include "fuzz_target.hpp"

namespace stridemap::fuzz {

class ByteReader {
 public:
  explicit ByteReader(Bytes data) : data_(data) {}

  bool empty() const { return pos_ >= data_.size(); }
  std::size_t remaining() const { return empty() ? 0 : data_.size() - pos_; }

  std::uint8_t byte() { return empty() ? 0 : data_[pos_++]; }
  template <typename T>
  T integer() {
    T value = 0;
    for (std::size_t i = 0; i < sizeof(T); ++i) value = static_cast<T>((value << 8) | static_cast<T>(byte()));
    return value;
  }
  /// A number in [lo, hi].
  std::uint64_t in_range(std::uint64_t lo, std::uint64_t hi) {
    const std::uint64_t span = hi - lo + 1;
    const std::uint64_t raw = span <= 0x100 ? byte() : span <= 0x10000 ? integer<std::uint16_t>() : integer<std::uint64_t>();
    return span == 0 ? raw : lo + raw % span;
  }
  /// Any double, NaN and infinities included.
  double any_double() {
    const std::uint64_t bits = integer<std::uint64_t>();
    double value;
    std::memcpy(&value, &bits, sizeof value);
    return value;
  }
  /// Up to `max` bytes, as they come.
  std::string text(std::size_t max) {
    const std::size_t n = in_range(0, max);
    std::string out;
    for (std::size_t i = 0; i < n && !empty(); ++i) out += static_cast<char>(byte());
    return out;
  }
  /// The rest of the input.
  std::string_view rest() {
    const std::string_view out = empty() ? std::string_view{} : as_text(data_.subspan(pos_));
    pos_ = data_.size();
    return out;
  }

 private:
  Bytes data_;
  std::size_t pos_ = 0;
};

/// Equal, or both NaN (a NaN's payload need not survive text).
inline bool same_number(double a, double b) { return a == b || (a != a && b != b); }

}  // namespace stridemap::fuzz
