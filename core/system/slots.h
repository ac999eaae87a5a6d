// A list refilled every frame without allocating: its first size() slots are in use, and the
// ones behind keep what they held (a string's room), so once the list has been as long as it gets
// its slots are only ever reused. The match's phrases and the announcer's queue and fates are
// such lists (docs/PERFORMANCE.md, "Allocations").
#pragma once

#include <algorithm>
#include <cstddef>
#include <span>
#include <vector>

namespace quantum::system {

template <class T>
class Slots {
 public:
  // The next slot, made or reused: a reused one still holds its last value, so set all of it.
  T& next() {
    if (used_ == slots_.size()) slots_.emplace_back();
    return slots_[used_++];
  }
  // Makes `n` slots ahead of their use.
  void make(size_t n) {
    if (slots_.size() < n) slots_.resize(n);
  }
  void clear() { used_ = 0; }
  // Takes slot k out; the later ones move up, and the slot goes behind them, kept (rotated,
  // never copied).
  void erase(size_t k) { erase(begin() + k); }
  void erase(T* slot) {
    std::rotate(slot, slot + 1, end());
    --used_;
  }

  size_t size() const { return used_; }
  bool empty() const { return used_ == 0; }
  T& operator[](size_t k) { return slots_[k]; }
  const T& operator[](size_t k) const { return slots_[k]; }
  T* begin() { return slots_.data(); }
  T* end() { return slots_.data() + used_; }
  std::span<const T> used() const { return {slots_.data(), used_}; }

 private:
  std::vector<T> slots_;
  size_t used_ = 0;
};

}  // namespace quantum::system
