#include "radiosity/compact_tables.hpp"

namespace lhr {

void CompactUints::widen() {
  std::vector<std::uint16_t> wide;
  wide.reserve(2 * data_.capacity());
  for (const std::uint16_t v : data_) {
    wide.push_back(v);
    wide.push_back(0);
  }
  data_ = std::move(wide);
  wide_ = true;
}

void CompactUints::set(std::size_t i, std::uint32_t value) {
  if (!wide_ && value > kNarrowMax) widen();
  if (!wide_) {
    data_[i] = static_cast<std::uint16_t>(value);
    return;
  }
  data_[2 * i] = static_cast<std::uint16_t>(value & 0xFFFFu);
  data_[2 * i + 1] = static_cast<std::uint16_t>(value >> 16);
}

void CompactUints::push_back(std::uint32_t value) {
  if (!wide_ && value > kNarrowMax) widen();
  if (!wide_) {
    data_.push_back(static_cast<std::uint16_t>(value));
    return;
  }
  data_.push_back(static_cast<std::uint16_t>(value & 0xFFFFu));
  data_.push_back(static_cast<std::uint16_t>(value >> 16));
}

void CompactUints::assign(std::size_t n, std::uint32_t value) {
  data_.clear();
  wide_ = false;
  grow(n, value);
}

void CompactUints::grow(std::size_t n, std::uint32_t value) {
  const std::size_t old = size();
  if (n <= old) return;
  if (!wide_ && value > kNarrowMax) widen();
  if (!wide_) {
    data_.resize(n, static_cast<std::uint16_t>(value));
    return;
  }
  data_.reserve(2 * n);
  for (std::size_t i = old; i < n; ++i) {
    data_.push_back(static_cast<std::uint16_t>(value & 0xFFFFu));
    data_.push_back(static_cast<std::uint16_t>(value >> 16));
  }
}

}  // namespace lhr
