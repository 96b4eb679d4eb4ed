#pragma once
// A first-in first-out queue over one growing array whose slots are reused:
// what a popped slot held (a scan's value vector, a message's characters)
// keeps its capacity for the element pushed into it next, so a queue that
// has reached its working length allocates nothing more. std::deque frees
// and allocates a block as elements pass through it, one per element for
// large elements such as scans.
#include <cstddef>
#include <utility>
#include <vector>

namespace stridemap {

template <typename T>
class RingQueue {
 public:
  bool empty() const { return size_ == 0; }
  std::size_t size() const { return size_; }
  std::size_t capacity() const { return slots_.size(); }

  /// The slot at the back, made part of the queue. It holds whatever the
  /// slot last held (or T{}): the caller assigns every field it uses, and
  /// assignment reuses the old contents' storage.
  T& push_slot() {
    if (size_ == slots_.size()) grow();
    T& slot = slots_[(head_ + size_) % slots_.size()];
    ++size_;
    return slot;
  }
  void push_back(const T& value) { push_slot() = value; }
  void push_back(T&& value) { push_slot() = std::move(value); }

  /// Removes the front element; its slot keeps its contents for reuse.
  void pop_front() {
    head_ = (head_ + 1) % slots_.size();
    --size_;
  }
  void clear() {
    head_ = 0;
    size_ = 0;
  }

  T& front() { return slots_[head_]; }
  const T& front() const { return slots_[head_]; }
  T& back() { return (*this)[size_ - 1]; }
  const T& back() const { return (*this)[size_ - 1]; }
  /// i-th element from the front.
  T& operator[](std::size_t i) { return slots_[(head_ + i) % slots_.size()]; }
  const T& operator[](std::size_t i) const { return slots_[(head_ + i) % slots_.size()]; }

  /// Makes room for `n` elements without growing later.
  void reserve(std::size_t n) {
    while (slots_.size() < n) grow();
  }
  /// The same, and `prepare(slot)` run on every free slot (say, to give a
  /// scan's values their storage), so that a longer queue later, when the
  /// elements come faster than they leave, does not allocate either.
  template <typename Prepare>
  void reserve(std::size_t n, Prepare prepare) {
    reserve(n);
    for (std::size_t i = size_; i < slots_.size(); ++i) prepare((*this)[i]);
  }

 private:
  // Doubles the array, the elements in order from slot 0; the free slots
  // keep their old contents (and capacity) too.
  void grow() {
    const std::size_t old = slots_.size();
    std::vector<T> bigger(old == 0 ? 8 : 2 * old);
    for (std::size_t i = 0; i < old; ++i) bigger[i] = std::move(slots_[(head_ + i) % old]);
    slots_ = std::move(bigger);
    head_ = 0;
  }

  std::vector<T> slots_;
  std::size_t head_ = 0;
  std::size_t size_ = 0;
};

}  // namespace stridemap
