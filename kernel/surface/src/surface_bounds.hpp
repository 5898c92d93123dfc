// The SurfaceFrame bounds pass's per-ISA kernel interface (surface_bounds_impl.hpp holds the kernel).
#pragma once
#include <cstddef>
#include <cstdint>

namespace houle::detail {

/// Over `count` node rows starting at `rows` (row stride `stride`), for node columns a .. b:
///   lo[i], hi[i]: min and max of the rows' values;
///   dx[i]: max |row[i + 1] - row[i]| (meaningful for i < b);
///   dy[i]: max |next row[i] - row[i]| over consecutive rows.
/// Whole batches are processed: columns up to b + 16 may be written and read (their values are
/// meaningless), so outputs need that much room and the rows that much readable memory after them
/// (the node arrays' row padding and the following rows or arrays provide it).
struct ColumnStatsJob {
  const float* rows;
  std::size_t stride;
  std::uint32_t count;  ///< >= 1
  std::size_t a, b;
  float* lo;
  float* hi;
  float* dx;
  float* dy;
};

}  // namespace houle::detail
