#include "houle/runtime/bulk_memory.hpp"

#include <cstdint>
#include <mutex>
#include <new>
#include <vector>

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

// A huge-page-aligned anonymous mapping of `size` bytes (whole huge pages), or null.
std::byte* map_huge(std::size_t size) {
  void* raw = mmap(nullptr, size + huge_page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (raw == MAP_FAILED) return nullptr;
  auto* base = static_cast<std::byte*>(raw);
  const std::uintptr_t aligned = (reinterpret_cast<std::uintptr_t>(base) + huge_page - 1) & ~(huge_page - 1);
  auto* p = reinterpret_cast<std::byte*>(aligned);
  const std::size_t head = std::size_t(p - base);
  if (head > 0) munmap(base, head);
  if (huge_page - head > 0) munmap(p + size, huge_page - head);
  madvise(p, size, MADV_HUGEPAGE);  // advice: without transparent huge pages these stay 4 KiB pages
  return p;
}

// Mappings freed by their last owner, kept for the next blocks: a build that follows another (a
// rebuilt scene, a benchmark) then writes to pages that are already there, where fresh ones would
// each be zeroed by the kernel on first touch (14 % of a Fig. 4 trace). At most `limit` bytes are
// kept; the oldest go first.
class MappingCache {
 public:
  static MappingCache& instance() {
    static MappingCache* cache = new MappingCache;  // never destroyed: blocks may outlive statics
    return *cache;
  }
  // A kept mapping of at least `size` bytes and at most twice that (the smallest such), or null.
  std::byte* take(std::size_t size, std::size_t& mapped) {
    const std::lock_guard<std::mutex> lock(mutex_);
    std::size_t best = kept_.size();
    for (std::size_t i = 0; i < kept_.size(); ++i) {
      const bool fits = kept_[i].size >= size && kept_[i].size <= 2 * size;
      if (fits && (best == kept_.size() || kept_[i].size < kept_[best].size)) best = i;
    }
    if (best == kept_.size()) return nullptr;
    const Mapping m = kept_[best];
    kept_.erase(kept_.begin() + std::ptrdiff_t(best));
    bytes_ -= m.size;
    mapped = m.size;
    return m.p;
  }
  void give(std::byte* p, std::size_t size) {
    std::vector<Mapping> evicted;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      kept_.push_back({p, size});
      bytes_ += size;
      std::size_t n = 0;
      while (bytes_ > limit) bytes_ -= kept_[n].size, evicted.push_back(kept_[n++]);
      kept_.erase(kept_.begin(), kept_.begin() + std::ptrdiff_t(n));
    }
    for (const Mapping& m : evicted) munmap(m.p, m.size);
  }
  void trim() {
    std::vector<Mapping> evicted;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      evicted.swap(kept_);
      bytes_ = 0;
    }
    for (const Mapping& m : evicted) munmap(m.p, m.size);
  }

 private:
  static constexpr std::size_t limit = std::size_t(64) << 20;
  struct Mapping {
    std::byte* p;
    std::size_t size;
  };
  std::mutex mutex_;
  std::vector<Mapping> kept_;  // oldest first
  std::size_t bytes_ = 0;
};

std::shared_ptr<std::byte[]> huge_block(std::size_t bytes) {
  const std::size_t size = (bytes + huge_page - 1) / huge_page * huge_page;
  std::size_t mapped = size;
  std::byte* p = MappingCache::instance().take(size, mapped);
  if (!p) p = map_huge(size);
  if (!p) return nullptr;
  return std::shared_ptr<std::byte[]>(p, [mapped](std::byte* q) { MappingCache::instance().give(q, mapped); });
}
#endif

}  // namespace

std::shared_ptr<std::byte[]> BulkLayout::allocate() const {
#if defined(__linux__) && defined(MADV_HUGEPAGE) && !defined(HOULE_ASAN)
  if (bytes_ >= huge_threshold) {
    if (auto block = huge_block(bytes_)) return block;
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

void BulkLayout::release_cached() {
#if defined(__linux__) && defined(MADV_HUGEPAGE) && !defined(HOULE_ASAN)
  MappingCache::instance().trim();
#endif
}

}  // namespace houle
