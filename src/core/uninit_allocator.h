// An allocator for scratch arrays that are resized without a fill. Internal to the
// core.
#pragma once

#include <memory>
#include <new>
#include <utility>

namespace pcl_vts {
namespace detail {

/// std::allocator whose value-initialisation (resize) leaves the elements
/// uninitialised, for scratch arrays written before they are read: LocalDelaunay's
/// window arrays (zero-filling them cost a memset of a window's size whenever a larger
/// window followed a smaller one; windows vary most on clustered points), the strip's
/// block lists, the grid stage's band buffers. Only for types whose default
/// initialisation leaves them indeterminate (std::pair, for one, is zeroed anyway).
template <typename T>
struct UninitAllocator : std::allocator<T> {
  template <typename U>
  struct rebind { // NOLINT(readability-identifier-naming): the allocator interface
    using other = UninitAllocator<U>; // NOLINT(readability-identifier-naming)
  };
  UninitAllocator() = default;
  template <typename U>
  UninitAllocator(const UninitAllocator<U>& /*other*/) noexcept // NOLINT
  {}
  template <typename U>
  void construct(U* ptr) noexcept
  {
    ::new (static_cast<void*>(ptr)) U;
  }
  template <typename U, typename... Args>
  void construct(U* ptr, Args&&... args)
  {
    ::new (static_cast<void*>(ptr)) U(std::forward<Args>(args)...);
  }
};

} // namespace detail
} // namespace pcl_vts
