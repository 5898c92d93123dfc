// One block for several large arrays that are built once per scene (traced ray samples), advised to
// huge pages on Linux when it is large.
//
// Why: on the 2-core VMs houle is measured on, the first touch of a 4 KiB page costs about 3.4 us;
// touching 8 MiB takes 6.9 ms in 4 KiB pages and 0.41 ms in 2 MiB huge pages. The Fig. 4 trace
// writes about 4 MiB of fresh samples, and before this a third of its time went to page faults.
// A block's huge pages outlive it: freed, they are kept (up to 64 MiB) for the next blocks, so that
// a build that follows another does not pay the kernel's zeroing of fresh pages again.
// Without transparent huge pages (or under AddressSanitizer, which cannot see inside an mmap) the
// block is an ordinary aligned allocation.
#pragma once
#include <cstddef>
#include <memory>
#include <vector>

#include "houle/runtime/assert.hpp"

namespace houle {

/// The layout of several arrays in one block. Each array starts on a 64-byte line and at least a
/// guard line follows it; under AddressSanitizer everything between an array's end and the next
/// array is poisoned, so an overrun of one array is still reported.
class BulkLayout {
 public:
  /// Reserves `n` elements of T; returns the array's byte offset in the block.
  template <class T>
  std::size_t add(std::size_t n) noexcept {
    const std::size_t at = bytes_, end = at + n * sizeof(T);
    bytes_ = round_up(end) + line;
    guards_.push_back({end, bytes_});
    return at;
  }
  std::size_t bytes() const noexcept { return bytes_; }
  /// An uninitialised block for this layout, freed with its last owner.
  std::shared_ptr<std::byte[]> allocate() const;
  /// Gives the huge pages kept from freed blocks back to the system.
  static void release_cached();

  template <class T>
  static T* at(std::byte* block, std::size_t offset) noexcept {
    HOULE_ASSERT(block != nullptr && offset % line == 0, "BulkLayout::at: an offset from add() into an allocated block");
    // Through void*: every offset is 64-byte aligned (add()), which -Wcast-align cannot know.
    return static_cast<T*>(static_cast<void*>(block + offset));
  }

 private:
  static constexpr std::size_t line = 64;
  static std::size_t round_up(std::size_t b) noexcept { return (b + line - 1) / line * line; }
  std::size_t bytes_ = 0;
  struct Gap {
    std::size_t begin, end;
  };
  std::vector<Gap> guards_;  // byte ranges after each array
};

}  // namespace houle
