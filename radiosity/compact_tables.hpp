#pragma once
// Storage for the interaction graphs' per-vertex tables, which on the room
// scenes were most of the graphs' own bytes (BENCHMARKS.md, "Per-vertex tables
// in 16 bits"): link offsets and vertex indices that fit in 16 bits in almost
// every graph, the importance per graph vertex, which only the shooter
// oracle's threshold reads, and the unoccluded form factors cached at the
// receiver's other vertices ("Graph storage under 30 %").

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace lhr {

// Unsigned 32-bit values kept in 16 bits each while all of them fit, in 32
// (two 16-bit halves, low first) from the first one that does not. A graph
// has fewer than 65 536 links and vertices unless it is one of a scene's few
// large ones, so its tables take half the room; the branch on the width is
// the same for every read of one table.
class CompactUints {
 public:
  static constexpr std::uint32_t kNarrowMax = 0xFFFF;

  CompactUints() = default;
  CompactUints(std::size_t n, std::uint32_t value) { assign(n, value); }

  std::size_t size() const { return wide_ ? data_.size() / 2 : data_.size(); }
  bool empty() const { return data_.empty(); }
  bool wide() const { return wide_; }
  std::uint32_t operator[](std::size_t i) const {
    if (!wide_) return data_[i];
    return static_cast<std::uint32_t>(data_[2 * i]) | (static_cast<std::uint32_t>(data_[2 * i + 1]) << 16);
  }
  std::uint32_t back() const { return (*this)[size() - 1]; }

  void set(std::size_t i, std::uint32_t value);
  void push_back(std::uint32_t value);
  // n copies of value; narrow again if value fits.
  void assign(std::size_t n, std::uint32_t value);
  // At least n values, the new ones `value` (a table that only grows).
  void grow(std::size_t n, std::uint32_t value);
  void reserve(std::size_t n) { data_.reserve(wide_ ? 2 * n : n); }
  void shrink_to_fit() { data_.shrink_to_fit(); }
  // Allocated bytes (capacity).
  std::size_t bytes() const { return data_.capacity() * sizeof(std::uint16_t); }

 private:
  void widen();

  std::vector<std::uint16_t> data_;
  bool wide_ = false;
};

// A float kept in its upper 16 bits (bfloat16: float's range, 8 significant
// bits, rounded to nearest even): a relative error of at most 2^-8, far below
// what an importance estimate knows, with the range of pixel counts of any
// image size.
class BFloat16 {
 public:
  BFloat16() = default;
  explicit BFloat16(float value) : bits_(round(value)) {}
  explicit BFloat16(double value) : BFloat16(static_cast<float>(value)) {}
  operator float() const { return std::bit_cast<float>(static_cast<std::uint32_t>(bits_) << 16); }

 private:
  static std::uint16_t round(float value) {
    if (std::isnan(value)) return 0x7FC0;
    const std::uint32_t bits = std::bit_cast<std::uint32_t>(value);
    return static_cast<std::uint16_t>((bits + 0x7FFFu + ((bits >> 16) & 1u)) >> 16);
  }
  std::uint16_t bits_ = 0;
};

// A non-negative value below 2, such as a form factor, in 16 bits: 5 bits of
// exponent for [2^-31, 2) and 11 significant bits after the leading one,
// rounded to nearest even, so within 2^-12 of the value. At 2^-31 and below
// it is 0, from 2 on its largest value (1.9995); NaN ("not computed yet") is
// kept. A float's 23 bits are more than the unoccluded caches need: what they
// hold multiplies a ratio interpolated between two vertices, far rougher than
// 2^-12 (docs/design.md, "Graph storage").
class UnitFloat16 {
 public:
  static constexpr std::uint16_t kNaN = 0xFFFF;
  static constexpr std::uint16_t kLargest = 0xFFFE;

  UnitFloat16() = default;
  explicit UnitFloat16(float value) : bits_(round(value)) {}
  explicit UnitFloat16(double value) : UnitFloat16(static_cast<float>(value)) {}
  operator float() const {
    if (bits_ == 0) return 0.0f;
    if (bits_ == kNaN) return std::numeric_limits<float>::quiet_NaN();
    return std::bit_cast<float>((static_cast<std::uint32_t>(bits_) + kBias) << kDropped);
  }
  bool is_nan() const { return bits_ == kNaN; }

 private:
  static constexpr int kDropped = 12;  // of float's 23 significant bits
  // Code 1 is float's smallest value above 2^-31 (biased exponent 96).
  static constexpr std::uint32_t kBias = (127u - 31u) << (23 - kDropped);
  static std::uint16_t round(float value) {
    if (std::isnan(value)) return kNaN;
    if (!(value > 0.0f)) return 0;
    const std::uint32_t bits = std::bit_cast<std::uint32_t>(value);
    const std::uint32_t kept =
        (bits + ((1u << (kDropped - 1)) - 1u) + ((bits >> kDropped) & 1u)) >> kDropped;
    if (kept <= kBias) return 0;
    return static_cast<std::uint16_t>(std::min<std::uint32_t>(kept - kBias, kLargest));
  }
  std::uint16_t bits_ = 0;
};

}  // namespace lhr
