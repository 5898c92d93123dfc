// BulkLayout: arrays carved from one block (houle/runtime/bulk_memory.hpp).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <numeric>
#include <vector>

#include "houle/runtime/bulk_memory.hpp"

#if defined(__linux__)
#include <sys/mman.h>  // MADV_HUGEPAGE: where bulk_memory.cpp maps huge pages
#endif

// As bulk_memory.cpp tells AddressSanitizer builds (GCC's macro, Clang's feature): there every block
// is an ordinary allocation.
#if defined(__SANITIZE_ADDRESS__)
#define HOULE_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define HOULE_TEST_ASAN 1
#endif
#endif

namespace {

// Offsets are 64-byte aligned and disjoint (a guard line between arrays), the block holds them all,
// and every byte of every array can be written and read back, for a small block (operator new) and
// one past the huge-page threshold (an mmap on Linux).
TEST(BulkMemory, ArraysAreAlignedDisjointAndWritable) {
  for (std::size_t n : {std::size_t(0), std::size_t(3), std::size_t(1003), std::size_t(300003)}) {
    houle::BulkLayout layout;
    const std::size_t a = layout.add<double>(n), b = layout.add<std::uint8_t>(n), c = layout.add<float>(n);
    EXPECT_EQ(a % 64, 0u);
    EXPECT_EQ(b % 64, 0u);
    EXPECT_EQ(c % 64, 0u);
    EXPECT_GE(b, a + n * sizeof(double) + 64);
    EXPECT_GE(c, b + n + 64);
    EXPECT_GE(layout.bytes(), c + n * sizeof(float) + 64);
    const auto block = layout.allocate();
    ASSERT_NE(block, nullptr);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(block.get()) % 64, 0u);
    double* x = houle::BulkLayout::at<double>(block.get(), a);
    auto* f = houle::BulkLayout::at<std::uint8_t>(block.get(), b);
    float* k = houle::BulkLayout::at<float>(block.get(), c);
    for (std::size_t i = 0; i < n; ++i) x[i] = double(i), f[i] = std::uint8_t(i), k[i] = float(i) * 0.5f;
    for (std::size_t i = 0; i < n; ++i) {
      ASSERT_EQ(x[i], double(i));
      ASSERT_EQ(f[i], std::uint8_t(i));
      ASSERT_EQ(k[i], float(i) * 0.5f);
    }
  }
}

// Copies share the block; it lives as long as its last owner.
TEST(BulkMemory, BlockLivesWithItsLastOwner) {
  houle::BulkLayout layout;
  const std::size_t a = layout.add<int>(1 << 20);  // 4 MiB: the huge-page path on Linux
  std::shared_ptr<std::byte[]> copy;
  {
    const auto block = layout.allocate();
    int* v = houle::BulkLayout::at<int>(block.get(), a);
    std::iota(v, v + (1 << 20), 0);
    copy = block;
  }
  const int* v = houle::BulkLayout::at<int>(copy.get(), a);
  EXPECT_EQ(v[0], 0);
  EXPECT_EQ(v[(1 << 20) - 1], (1 << 20) - 1);
}

#if defined(__linux__) && defined(MADV_HUGEPAGE) && !defined(HOULE_TEST_ASAN)
// A freed huge-page block is kept and handed to the next block of about its size (a rebuilt scene
// writes to pages already there); release_cached() gives the kept pages back.
TEST(BulkMemory, FreedHugeBlocksAreReusedUntilReleased) {
  houle::BulkLayout::release_cached();
  houle::BulkLayout layout;
  layout.add<double>(std::size_t(1) << 19);  // 4 MiB
  std::byte* first = nullptr;
  {
    const auto block = layout.allocate();
    first = block.get();
  }
  {
    const auto block = layout.allocate();
    EXPECT_EQ(block.get(), first);
  }
  // Not for a block of less than half its size: it would hold on to too much memory.
  houle::BulkLayout small;
  small.add<double>(std::size_t(1) << 17);  // 1 MiB
  EXPECT_NE(small.allocate().get(), first);
  houle::BulkLayout::release_cached();
}
#endif

#if defined(HOULE_TEST_ASAN)
// Under AddressSanitizer (the asan stage) the gap after an array is poisoned: reading one element
// past a 10-double array, still inside the block, is reported.
TEST(BulkMemory, OverrunIntoTheGapIsReportedUnderAsan) {
  houle::BulkLayout layout;
  const std::size_t a = layout.add<double>(10);
  layout.add<double>(10);
  const auto block = layout.allocate();
  const volatile double* x = houle::BulkLayout::at<double>(block.get(), a);
  EXPECT_DEATH((void)x[10], "use-after-poison");
}
#endif

}  // namespace
