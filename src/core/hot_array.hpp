// Storage for the arrays the contact loop touches every step, the particle
// arrays it reads at random (a contact's partner) and the candidate arrays it
// streams: std::vector with an allocator that asks Linux for transparent huge
// pages (2 MiB) on large arrays.
//
// Why: a contact's partner can lie anywhere in memory, and with 4 KiB pages a
// 100,000-sphere scene's particle arrays alone span ~4,000 pages (8 arrays of
// 0.8-6.4 MB), more than the CPU's second-level TLB holds, so many partners
// cost a page walk besides the cache miss; and the hardware prefetchers stop
// at 4 KiB page boundaries in the streamed arrays. With 2 MiB pages the same
// arrays fit in about a dozen entries (docs/performance.md, "Huge pages"). Most distributions set
// transparent huge pages to "madvise": a program gets them only where it asks,
// which is what this allocator does (madvise(MADV_HUGEPAGE) on fresh memory,
// before the vector first writes it). Elsewhere (THP off, another OS) it is an
// ordinary aligned allocation: the same results, only the speed differs.
#pragma once

#include <cstddef>
#include <cstdint>
#include <new>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace granule {

// AddressSanitizer checks only what operator new hands out: under it, every
// array takes the ordinary path so that its bounds stay checked.
#if defined(__linux__) && defined(MADV_HUGEPAGE) && !defined(__SANITIZE_ADDRESS__)
#define GRANULE_HUGE_PAGES 1
#else
#define GRANULE_HUGE_PAGES 0
#endif

template <typename T>
struct HugePageAllocator {
  using value_type = T;
  // Below this an array fits in a few ordinary pages; huge ones would only waste memory.
  static constexpr std::size_t huge_min_bytes = std::size_t{1} << 20;
  static constexpr std::size_t huge_page = std::size_t{2} << 20;
  static constexpr std::size_t small_alignment = alignof(T) > 64 ? alignof(T) : 64;
  // Readable bytes past the last element: the batched pair loop loads a 3D
  // vector (24 bytes) as four doubles (32 bytes, one instruction) and drops
  // the fourth, so the last particle's vector must be followed by 8 more bytes.
  static constexpr std::size_t tail_bytes = 32;

  HugePageAllocator() = default;
  template <typename U>
  HugePageAllocator(const HugePageAllocator<U>&) noexcept {}

  T* allocate(std::size_t n) {
    if (n > (static_cast<std::size_t>(-1) - tail_bytes) / sizeof(T))
      throw std::bad_array_new_length();
    const std::size_t bytes = n * sizeof(T) + tail_bytes;
#if GRANULE_HUGE_PAGES
    if (bytes >= huge_min_bytes) {
      // A fresh mapping of whole huge pages on a huge-page boundary (the
      // slack around it given back): its first touch faults huge pages in.
      const std::size_t length = round_up(bytes);
      void* raw = mmap(nullptr, length + huge_page, PROT_READ | PROT_WRITE,
                       MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
      if (raw == MAP_FAILED) throw std::bad_alloc();
      char* const start = static_cast<char*>(raw);
      char* const aligned =
          start + (huge_page - reinterpret_cast<std::uintptr_t>(raw) % huge_page) % huge_page;
      if (aligned > start) munmap(start, static_cast<std::size_t>(aligned - start));
      char* const end = start + length + huge_page;
      if (end > aligned + length)
        munmap(aligned + length, static_cast<std::size_t>(end - (aligned + length)));
      madvise(aligned, length, MADV_HUGEPAGE);  // a hint: refused (THP off) it changes nothing
      return reinterpret_cast<T*>(aligned);
    }
#endif
    return static_cast<T*>(::operator new(bytes, std::align_val_t(small_alignment)));
  }

  void deallocate(T* p, std::size_t n) noexcept {
    [[maybe_unused]] const std::size_t bytes = n * sizeof(T) + tail_bytes;
#if GRANULE_HUGE_PAGES
    if (bytes >= huge_min_bytes) {
      munmap(p, round_up(bytes));
      return;
    }
#endif
    ::operator delete(p, std::align_val_t(small_alignment));
  }

 private:
  static std::size_t round_up(std::size_t bytes) {
    return (bytes + huge_page - 1) / huge_page * huge_page;
  }
};

template <typename T, typename U>
bool operator==(const HugePageAllocator<T>&, const HugePageAllocator<U>&) {
  return true;
}
template <typename T, typename U>
bool operator!=(const HugePageAllocator<T>&, const HugePageAllocator<U>&) {
  return false;
}

// An array the contact loop touches every step (see the top of this file).
template <typename T>
using HotArray = std::vector<T, HugePageAllocator<T>>;

}  // namespace granule
