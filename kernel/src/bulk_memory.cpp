#include "houle/kernel/bulk_memory.hpp"

#include <cstdint>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

#if defined(__SANITIZE_ADDRESS__)
#define HOULE_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define HOULE_ASAN 1
#endif
#endif
#if defined(HOULE_ASAN)
#include <sanitizer/asan_interface.h>
#endif

namespace houle {
namespace {

constexpr std::align_val_t alignment{64};

#if defined(__linux__) && defined(MADV_HUGEPAGE) && !defined(HOULE_ASAN)
constexpr std::size_t huge_page = std::size_t(2) << 20;
// Below this, rounding up to whole huge pages would cost more memory than the faults it saves.
constexpr std::size_t huge_threshold = std::size_t(1) << 20;

// A huge-page-aligned anonymous mapping of whole huge pages, or null.
std::shared_ptr<std::byte[]> map_huge(std::size_t bytes) {
  const std::size_t size = (bytes + huge_page - 1) / huge_page * huge_page;
  void* raw = mmap(nullptr, size + huge_page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (raw == MAP_FAILED) return nullptr;
  auto* base = static_cast<std::byte*>(raw);
  const std::uintptr_t aligned = (reinterpret_cast<std::uintptr_t>(base) + huge_page - 1) & ~(huge_page - 1);
  auto* p = reinterpret_cast<std::byte*>(aligned);
  const std::size_t head = std::size_t(p - base);
  if (head > 0) munmap(base, head);
  if (huge_page - head > 0) munmap(p + size, huge_page - head);
  madvise(p, size, MADV_HUGEPAGE);  // advice: without transparent huge pages these stay 4 KiB pages
  return std::shared_ptr<std::byte[]>(p, [size](std::byte* q) { munmap(q, size); });
}
#endif

}  // namespace

std::shared_ptr<std::byte[]> BulkLayout::allocate() const {
#if defined(__linux__) && defined(MADV_HUGEPAGE) && !defined(HOULE_ASAN)
  if (bytes_ >= huge_threshold) {
    if (auto block = map_huge(bytes_)) return block;
  }
#endif
  auto* p = static_cast<std::byte*>(::operator new(bytes_, alignment));
#if defined(HOULE_ASAN)
  for (const Gap& g : guards_) ASAN_POISON_MEMORY_REGION(p + g.begin, g.end - g.begin);
  const std::size_t size = bytes_;
  return std::shared_ptr<std::byte[]>(p, [size](std::byte* q) {
    ASAN_UNPOISON_MEMORY_REGION(q, size);
    ::operator delete(q, alignment);
  });
#else
  return std::shared_ptr<std::byte[]>(p, [](std::byte* q) { ::operator delete(q, alignment); });
#endif
}

}  // namespace houle
