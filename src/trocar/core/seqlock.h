#pragma once
/// A single-writer, many-reader exchange of one trivially copyable struct (one consistent
/// struct per publish, docs/runtime.md "Exchange"). The writer never waits; a reader copies the
/// payload and retries if a publish overlapped its copy, so it never returns halves of two samples.
///
/// Seqlock with an atomic payload (Boehm, "Can seqlocks get along with programming language
/// memory models?", MSPC 2012, fig. 6): the payload is stored as relaxed atomic 64-bit words, so
/// concurrent reads and writes are not a data race in the C++ model (and ThreadSanitizer agrees);
/// the sequence counter is odd while a publish is in progress. Lives in core because the device
/// drivers (a socket thread → the haptic tick) and the runtime (physics → haptic → consumers)
/// both exchange samples this way.
#include <array>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace trocar {

template <typename T>
class Seqlock {
  // Copied word by word. Eigen's fixed-size vectors and quaternions have user-written copy
  // constructors (so not is_trivially_copyable) but are plain arrays of doubles underneath; a
  // payload must be made of such values: no pointers to owned memory, nothing to destroy.
  static_assert(std::is_trivially_destructible_v<T> && std::is_standard_layout_v<T>,
                "a Seqlock payload is copied word by word");

 public:
  Seqlock() { publish(T{}); sequence_.store(0, std::memory_order_relaxed); }
  explicit Seqlock(const T& initial) { publish(initial); sequence_.store(0, std::memory_order_relaxed); }
  Seqlock(const Seqlock&) = delete;
  Seqlock& operator=(const Seqlock&) = delete;

  /// Publishes a new value (one writer thread only). Wait-free, no allocation.
  void publish(const T& value) {
    std::array<std::uint64_t, kWords> words{};
    std::memcpy(words.data(), static_cast<const void*>(&value), sizeof(T));
    const std::uint64_t s = sequence_.load(std::memory_order_relaxed);
    sequence_.store(s + 1, std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_release);
    for (std::size_t i = 0; i < kWords; ++i) payload_[i].store(words[i], std::memory_order_relaxed);
    sequence_.store(s + 2, std::memory_order_release);
  }

  /// Copies the last complete publish into out and returns its publish count (0 = the initial
  /// value). Lock-free: retries only while a publish overlaps the copy.
  std::uint64_t read(T& out) const {
    std::array<std::uint64_t, kWords> words{};
    std::uint64_t before = 0;
    for (;;) {
      before = sequence_.load(std::memory_order_acquire);
      if (before & 1U) continue;  // a publish is in progress
      for (std::size_t i = 0; i < kWords; ++i) words[i] = payload_[i].load(std::memory_order_relaxed);
      std::atomic_thread_fence(std::memory_order_acquire);
      if (sequence_.load(std::memory_order_relaxed) == before) break;
    }
    std::memcpy(static_cast<void*>(&out), words.data(), sizeof(T));
    return before / 2;
  }

  /// The last complete publish.
  T load() const {
    T out;
    read(out);
    return out;
  }

  /// Publishes so far (a reader's cheap "is there something new?" check).
  std::uint64_t publishes() const { return sequence_.load(std::memory_order_acquire) / 2; }

 private:
  static constexpr std::size_t kWords = (sizeof(T) + 7) / 8;
  std::atomic<std::uint64_t> sequence_{0};
  std::array<std::atomic<std::uint64_t>, kWords> payload_{};
};

}  // namespace trocar
