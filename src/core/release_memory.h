#pragma once

#include <cstdlib> // defines __GLIBC__ where the C library is glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif
#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

#include <cstddef>
#include <cstdint>

namespace pcl_vts {
namespace detail {

/// Inputs with fewer points keep their freed memory until the pipeline returns (a few
/// MB at most): handing it back (malloc_trim, madvise) and faulting it in again cost
/// more than the peak it saves. At 1e4 points the trims and refaults were 7 % of a
/// first call (bench_triangulation vts jittered 10000: 629 -> 475 page faults).
constexpr std::size_t RELEASE_MIN_POINTS = std::size_t{1} << 16;

/// Hands the pages of freed memory back to the system. glibc keeps the freed chunks
/// below the top of its heap resident until then, so arrays released between two
/// stages (the strips once merged, the grid's cells) would otherwise still count in
/// the resident set beside the arrays allocated after them: without it
/// bench_triangulation vts jittered 1e6 reported 132.9 bytes per point above the
/// input instead of 87.2. A no-op elsewhere.
inline void releaseFreedMemory()
{
#if defined(__GLIBC__)
  ::malloc_trim(0);
#endif
}

#if defined(__linux__)
/// madvise(advice) over the whole pages inside [begin, end) (none when it holds no
/// whole page): the partial pages at either end belong to neighbouring data.
inline void adviseWholePages(const void* begin, const void* end, int advice)
{
  static const auto page = static_cast<std::uintptr_t>(::sysconf(_SC_PAGESIZE));
  const std::uintptr_t first =
      (reinterpret_cast<std::uintptr_t>(begin) + page - 1) / page * page;
  const std::uintptr_t last = reinterpret_cast<std::uintptr_t>(end) / page * page;
  if (last > first)
    ::madvise(reinterpret_cast<void*>(first), last - first, advice);
}
#endif

/// Hands the whole pages inside [begin, end) of a live allocation back to the system
/// (Linux): they read as zeros afterwards and count in the resident set again only
/// once written. A no-op elsewhere.
inline void releasePages(const void* begin, const void* end)
{
#if defined(__linux__)
  adviseWholePages(begin, end, MADV_DONTNEED);
#else
  (void)begin;
  (void)end;
#endif
}

/// releasePages(begin, end) for an array handed back piece by piece from its start:
/// returns where the next piece should begin (end rounded down to a page), so that
/// consecutive calls hand back every whole page once.
inline const void* releasePagesUpTo(const void* begin, const void* end)
{
#if defined(__linux__)
  static const auto page = static_cast<std::uintptr_t>(::sysconf(_SC_PAGESIZE));
  releasePages(begin, end);
  const std::uintptr_t last = reinterpret_cast<std::uintptr_t>(end) / page * page;
  return last > reinterpret_cast<std::uintptr_t>(begin)
             ? reinterpret_cast<const void*>(last)
             : begin;
#else
  (void)end;
  return begin;
#endif
}

/// Faults in the whole pages inside [begin, end) of a live allocation in one system
/// call (Linux >= 5.14, MADV_POPULATE_WRITE), for an array about to be written in
/// full: without it each of its pages faults on its first write, a trap apiece (in a
/// VM an exit too). The contents are unchanged. A no-op elsewhere
/// (and where the system refuses).
inline void populatePages(const void* begin, const void* end)
{
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
  adviseWholePages(begin, end, MADV_POPULATE_WRITE);
#else
  (void)begin;
  (void)end;
#endif
}

/// v's capacity made at least `count` for an array whose old entries are not read
/// again: when it grows, they are dropped instead of copied (the copy would touch
/// the new block first) and the new block's first `count` entries' pages are faulted
/// in at once (populatePages).
template <class Vector>
inline void reserveDiscarding(Vector& v, std::size_t count)
{
  if (v.capacity() >= count)
    return;
  Vector().swap(v);
  v.reserve(count);
  populatePages(v.data(), v.data() + count);
}

/// Faults in the pages of an array written from its start on, a chunk ahead of the
/// writes (populatePages): the next `count` elements appended to `v` (within its
/// capacity) are resident after the call. `populated` (start it at nullptr, again
/// whenever v is reallocated) marks where the pages populated so far end. Chunks of
/// 64 KiB: the pages stay in cache between the kernel's zeroing and the writes, which
/// populating a large array at once would lose (a second trip to memory).
template <class Vector>
inline void populateAhead(const Vector& v, std::size_t count, const void*& populated)
{
  constexpr std::size_t CHUNK = std::size_t{1} << 16;
  const char* const begin = reinterpret_cast<const char*>(v.data());
  const char* const end = reinterpret_cast<const char*>(v.data() + v.capacity());
  const char* const need = reinterpret_cast<const char*>(
      v.data() + (v.size() + count < v.capacity() ? v.size() + count : v.capacity()));
  // `populated` may point into an earlier allocation of v: compared as addresses
  // (comparing unrelated pointers with < is unspecified).
  const auto address = [](const void* pointer) {
    return reinterpret_cast<std::uintptr_t>(pointer);
  };
  const char* from = static_cast<const char*>(populated);
  if (from == nullptr || address(from) < address(begin) || address(from) > address(end))
    from = reinterpret_cast<const char*>(v.data() + v.size());
  if (need <= from)
    return;
  const char* const upto =
      static_cast<std::size_t>(end - need) > CHUNK ? need + CHUNK : end;
  populatePages(from, upto);
  populated = upto;
}

/// v.resize(count), or v.assign(count, value) when `value` is given, with the pages
/// faulted in a chunk ahead of the fill (populateAhead) instead of a trap per page.
template <class Vector, class... Value>
inline void fillPopulated(Vector& v, std::size_t count, const Value&... value)
{
  static_assert(sizeof...(Value) <= 1, "one value at most");
  if constexpr (sizeof...(Value) == 1)
    v.clear();
  v.reserve(count);
  const void* populated = nullptr;
  constexpr std::size_t STEP =
      (std::size_t{1} << 16) / sizeof(typename Vector::value_type);
  while (v.size() < count) {
    const std::size_t next = count - v.size() > STEP ? v.size() + STEP : count;
    populateAhead(v, next - v.size(), populated);
    v.resize(next, value...);
  }
  if (v.size() > count)
    v.resize(count);
}

} // namespace detail
} // namespace pcl_vts
