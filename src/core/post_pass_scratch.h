// Memory handed to the post-passes for their scratch (internal to the core): a
// resident block its owner no longer reads (runVtsPipeline's input once the
// triangulation has read it) serves the trim's own medians and rows' entries, whose
// pages are then resident already instead of faulted in and zeroed by the kernel one
// by one (a fresh page costs ~1-2 us on this VM).
#pragma once

#include "release_memory.h"

#include <pcl_vts/core/reconstruct_surface.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <vector>

namespace pcl_vts::detail {

/// A resident block of memory, dead for its owner until the post-passes return, or
/// none (bytes 0). Taken by the first scratchArray it fits.
struct ScratchBlock {
  void* data = nullptr;
  std::size_t bytes = 0;
  /// The vector whose storage the block is, when it is one (splitForOwn).
  std::vector<double>* owner = nullptr;
};

/// The trim's share of `block` when it is a vector's storage: the vector, whose
/// first n doubles ownMedians takes over for the own medians (own grows no further
/// in the trim), and the block past them for the rows (left in block). Null, and
/// block unchanged, when it is not a vector's or cannot hold n doubles.
inline std::vector<double>* splitForOwn(ScratchBlock& block, std::size_t n)
{
  std::vector<double>* const owner = block.owner;
  if (owner == nullptr || block.data != owner->data() ||
      block.bytes / sizeof(double) < n)
    return nullptr;
  block.data = owner->data() + n;
  block.bytes -= n * sizeof(double);
  block.owner = nullptr;
  return owner;
}

/// delete[] for an array of its own, nothing for one inside a ScratchBlock (its
/// owner frees the block).
struct ScratchDelete {
  bool owned = true;
  template <class T>
  void operator()(T* array) const
  {
    if (owned)
      delete[] array;
  }
};

template <class T>
using ScratchArray = std::unique_ptr<T[], ScratchDelete>;

/// An uninitialised array of count T: inside block when it fits there (block is
/// then emptied: it serves one array), else a new one with its pages faulted in at
/// once (populatePages).
template <class T>
ScratchArray<T> scratchArray(std::size_t count, ScratchBlock& block)
{
  static_assert(std::is_trivially_default_constructible_v<T> &&
                    std::is_trivially_destructible_v<T>,
                "the block's bytes are reused without construction");
  const auto address = reinterpret_cast<std::uintptr_t>(block.data);
  if (block.data != nullptr && count <= block.bytes / sizeof(T) &&
      address % alignof(T) == 0) {
    // The block's old objects end here; T's lifetime starts without any write.
    T* const array =
        std::uninitialized_default_construct_n(static_cast<T*>(block.data), count) -
        count;
    block = ScratchBlock{};
    return ScratchArray<T>(array, ScratchDelete{false});
  }
  ScratchArray<T> array(new T[count]);
  populatePages(array.get(), array.get() + count);
  return array;
}

/// reconstructSurface with `scratch` for the trim's rows (VertexRows).
Status reconstructSurface(TriangleMesh& mesh, const ReconstructionOptions& options,
                          ReconstructionDiagnostics& diagnostics, ScratchBlock scratch);

} // namespace pcl_vts::detail
