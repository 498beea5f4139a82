// The snapshot exchange: a Seqlock written at 10 kHz and read by two threads never yields a torn
// struct (each payload carries a checksum of its own words), and the SPSC ring keeps order.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <thread>

#include "trocar/core/seqlock.h"
#include "trocar/runtime/realtime.h"
#include "trocar/runtime/spsc_ring.h"

namespace trocar {
namespace {

struct Payload {
  std::uint64_t index = 0;
  std::array<std::uint64_t, 30> words{};  // 248 bytes: many words, so a torn copy is likely if possible
  std::uint64_t checksum = 0;
};

std::uint64_t checksum_of(const Payload& p) {
  std::uint64_t h = 1469598103934665603ULL ^ p.index;
  for (std::uint64_t w : p.words) h = (h ^ w) * 1099511628211ULL;
  return h;
}

Payload make(std::uint64_t i) {
  Payload p;
  p.index = i;
  for (std::size_t k = 0; k < p.words.size(); ++k) p.words[k] = i * 2654435761ULL + k;
  p.checksum = checksum_of(p);
  return p;
}

TEST(Seqlock, TenKilohertzWriterTwoReadersNeverTear) {
  Seqlock<Payload> lock(make(0));
  std::atomic<bool> done{false};
  constexpr std::uint64_t kPublishes = 3000;  // 0.3 s at 10 kHz
  const auto reader = [&](std::uint64_t& reads, std::uint64_t& torn, std::uint64_t& backwards) {
    std::uint64_t last = 0;
    while (!done.load(std::memory_order_acquire)) {
      Payload p;
      lock.read(p);
      ++reads;
      if (checksum_of(p) != p.checksum || p.words[29] != p.index * 2654435761ULL + 29) ++torn;
      if (p.index < last) ++backwards;
      last = p.index;
    }
  };
  std::uint64_t reads_a = 0, torn_a = 0, back_a = 0, reads_b = 0, torn_b = 0, back_b = 0;
  std::thread a([&] { reader(reads_a, torn_a, back_a); });
  std::thread b([&] { reader(reads_b, torn_b, back_b); });
  std::int64_t next = monotonic_ns();
  for (std::uint64_t i = 1; i <= kPublishes; ++i) {
    next += 100000;  // 100 µs
    wait_until(next, 20000);
    lock.publish(make(i));
  }
  done.store(true, std::memory_order_release);
  a.join();
  b.join();
  EXPECT_EQ(torn_a, 0u);
  EXPECT_EQ(torn_b, 0u);
  EXPECT_EQ(back_a, 0u);  // a reader never sees an older publish after a newer one
  EXPECT_EQ(back_b, 0u);
  EXPECT_GT(reads_a, kPublishes / 10);  // the readers were really running beside the writer
  EXPECT_GT(reads_b, kPublishes / 10);
  EXPECT_EQ(lock.publishes(), kPublishes);  // the constructor's initial value is not a publish
  EXPECT_EQ(lock.load().index, kPublishes);
}

TEST(SpscRing, KeepsOrderAcrossThreadsAndCountsDrops) {
  SpscRing<std::uint64_t> ring(1024);
  constexpr std::uint64_t kCount = 200000;
  std::atomic<bool> produced{false};
  std::uint64_t pushed = 0;
  std::thread producer([&] {
    for (std::uint64_t i = 0; i < kCount; ++i)
      if (ring.push(i)) ++pushed;
    produced.store(true, std::memory_order_release);
  });
  std::uint64_t popped = 0, last = 0, out_of_order = 0, v = 0;
  bool first = true;
  for (;;) {
    if (ring.pop(v)) {
      if (!first && v <= last) ++out_of_order;
      first = false;
      last = v;
      ++popped;
    } else if (produced.load(std::memory_order_acquire)) {
      while (ring.pop(v)) ++popped;
      break;
    }
  }
  producer.join();
  EXPECT_EQ(out_of_order, 0u);
  EXPECT_EQ(popped, pushed);
  EXPECT_EQ(pushed + ring.dropped(), kCount);
}

TEST(SpscRing, FullRingDropsTheNewest) {
  SpscRing<int> ring(3);  // rounded up to 4
  for (int i = 0; i < 6; ++i) ring.push(i);
  EXPECT_EQ(ring.dropped(), 2u);
  int v = -1;
  for (int want = 0; want < 4; ++want) {
    ASSERT_TRUE(ring.pop(v));
    EXPECT_EQ(v, want);
  }
  EXPECT_FALSE(ring.pop(v));
}

}  // namespace
}  // namespace trocar
