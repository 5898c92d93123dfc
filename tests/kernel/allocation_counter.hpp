// Counts heap allocations made while an AllocationCounter is alive (allocation_counter.cpp replaces
// the global operator new of the test program that links it), for the allocation-free frame loop test.
#pragma once

namespace houle::test {

class AllocationCounter {
 public:
  AllocationCounter();
  ~AllocationCounter();
  AllocationCounter(const AllocationCounter&) = delete;
  AllocationCounter& operator=(const AllocationCounter&) = delete;
  /// Allocations since construction.
  long count() const;
};

}  // namespace houle::test
