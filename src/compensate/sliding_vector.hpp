#pragma once
// A queue that grows at the back, drops from the front and is indexed at the cost of a
// vector's: verify's search reads pieces of its window by index a thousand times a line,
// and std::deque's indexing (a division and two loads per element) was a sixth of it.
#include <cstddef>
#include <utility>
#include <vector>

namespace ccomp::compensate {

/// Elements in a vector behind a moving head: dropping from the front moves the head, and
/// the dropped elements are erased once there are as many as are kept and at least
/// kReclaimAt (each element is moved about once on average): at most max(kept, kReclaimAt -
/// 1) dropped ones are held. (The vector's capacity stays at its largest.)
template <class T>
class SlidingVector {
 public:
  void push_back(T value) { items_.push_back(std::move(value)); }
  template <class... Args>
  T& emplace_back(Args&&... args) {
    return items_.emplace_back(std::forward<Args>(args)...);
  }
  /// Drops the first n elements (n <= size()).
  void drop_front(std::size_t n) {
    head_ += n;
    if (head_ == items_.size()) {
      clear();
    } else if (head_ >= kReclaimAt && head_ >= items_.size() - head_) {
      items_.erase(items_.begin(), items_.begin() + static_cast<std::ptrdiff_t>(head_));
      head_ = 0;
    }
  }
  void clear() {
    items_.clear();
    head_ = 0;
  }
  [[nodiscard]] std::size_t size() const { return items_.size() - head_; }
  [[nodiscard]] bool empty() const { return size() == 0; }
  [[nodiscard]] const T& operator[](std::size_t i) const { return items_[head_ + i]; }
  [[nodiscard]] const T& front() const { return items_[head_]; }
  [[nodiscard]] T& back() { return items_.back(); }

 private:
  /// Fewer dropped elements than this are left where they are: moving them costs more than
  /// the space.
  static constexpr std::size_t kReclaimAt = 256;
  std::vector<T> items_;
  std::size_t head_ = 0;
};

}  // namespace ccomp::compensate
