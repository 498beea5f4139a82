#pragma once
/// A single-producer, single-consumer triple buffer (one consistent struct per publish by an
/// atomic index swap, docs/runtime.md "Exchange"). The writer fills its back slot and swaps it with
/// the middle one; the reader swaps the middle slot into its front when a new one was published.
/// Neither side ever waits and no slot is shared: unlike a Seqlock the payload may own heap memory
/// (vectors sized once and reused), which a renderer's snapshot of a deforming mesh needs.
#include <array>
#include <atomic>
#include <cstdint>

namespace trocar {

template <class T>
class TripleBuffer {
 public:
  /// The writer's slot: fill it, then publish().
  T& back() { return slots_[back_]; }
  /// Makes the back slot the newest; the writer gets the previous middle slot to fill next.
  void publish() {
    const std::uint32_t old = middle_.exchange(back_ | kFresh, std::memory_order_acq_rel);
    back_ = old & kIndex;
  }
  /// Takes the newest published slot if there is one; returns true when front() changed.
  bool update() {
    if ((middle_.load(std::memory_order_relaxed) & kFresh) == 0) return false;
    const std::uint32_t old = middle_.exchange(front_, std::memory_order_acq_rel);
    front_ = old & kIndex;
    return true;
  }
  /// The reader's slot: the newest snapshot it has taken (default-constructed before the first).
  const T& front() const { return slots_[front_]; }
  /// All three slots, e.g. to size them before the threads start.
  std::array<T, 3>& slots() { return slots_; }

 private:
  static constexpr std::uint32_t kFresh = 4;
  static constexpr std::uint32_t kIndex = 3;
  std::array<T, 3> slots_{};
  std::atomic<std::uint32_t> middle_{1};
  std::uint32_t back_ = 0;   // writer only
  std::uint32_t front_ = 2;  // reader only
};

}  // namespace trocar
