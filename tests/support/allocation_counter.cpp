#include "allocation_counter.h"

#include <cstdlib>
#include <new>
#include <vector>

namespace trocar::test {

std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};

namespace {

void* counted_allocate(std::size_t size) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}

void* counted_allocate_nothrow(std::size_t size) noexcept {
  try {
    return counted_allocate(size);
  } catch (...) {
    return nullptr;
  }
}

}  // namespace

long probe_counted_allocations() {
  g_allocations = 0;
  g_counting = true;
  auto* probe = new std::vector<int>(10);
  g_counting = false;
  delete probe;
  return g_allocations.load();
}

}  // namespace trocar::test

void* operator new(std::size_t size) { return trocar::test::counted_allocate(size); }
void* operator new[](std::size_t size) { return trocar::test::counted_allocate(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept { return trocar::test::counted_allocate_nothrow(size); }
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept { return trocar::test::counted_allocate_nothrow(size); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
