// The surface room's per-ISA function table (see houle/simd/dispatch.hpp).
#pragma once
#include <cstddef>
#include <cstdint>

#include "houle/surface/camera.hpp"
#include "houle/surface/capillary.hpp"
#include "houle/surface/gerstner.hpp"
#include "houle/surface/train_grid.hpp"
#include "march_context.hpp"
#include "surface_bounds.hpp"

namespace houle::detail {

struct SurfaceTable {
  void (*camera_row_rays)(const Camera&, std::uint32_t, std::uint32_t, std::size_t, float, float, float*, float*,
                          float*) noexcept;
  void (*gerstner_eval)(const GerstnerFrame&, const float*, const float*, std::size_t, GerstnerOutput, int) noexcept;
  void (*capillary_eval)(const CapillaryFrame&, const float*, const float*, const float*, std::size_t, float*, float*,
                         float*) noexcept;
  void (*march_rays)(const MarchContext&, const MarchRays&, std::size_t, const MarchHits&) noexcept;
  void (*surface_column_stats)(const ColumnStatsJob&) noexcept;
  void (*train_grid_eval)(const TrainGridFrame&, const float*, const float*, std::size_t, GerstnerOutput) noexcept;
  void (*train_grid_eval_filtered)(const TrainGridFrame&, const float*, const float*, std::size_t, const NodeFootprint&,
                                   GerstnerOutput, float*, TrainGridKeep) noexcept;
};

}  // namespace houle::detail
