// A sea state's surface over a long record (docs/physics.md 2.9): four standard deviations of the
// height at an offshore point are Hs, in deep open water and offshore of a beach where every component
// is traced (what `houle probe --times` prints; the cli test does it through the command).
#include <gtest/gtest.h>

#include <cmath>

#include "houle/sim/scene.hpp"
#include "open_sea.hpp"
#include "houle/sim/sea_surface.hpp"
#include "houle/sim/wave_rays.hpp"

namespace {

using houle_test::open_sea;

// 4 standard deviations of the surface height at (x, y) over an hour (houle probe --times).
double record_hs(const houle::Scene& scene, float x, float y) {
  auto field = houle::trace_wave_field(scene, 2);
  EXPECT_TRUE(field.ok());
  if (!field.ok()) return 0.0;
  auto sea = houle::SeaSurface::build(scene, field.value(), 1.0f, houle::SeaParts::drop, 2);
  EXPECT_TRUE(sea.ok());
  if (!sea.ok()) return 0.0;
  double sum = 0.0, sum2 = 0.0;
  const int n = 14400;
  for (int i = 0; i < n; ++i) {
    sea->set_time(0.25 * i);
    float h, gx, gy;
    sea->eval(&x, &y, 1, &h, &gx, &gy);
    sum += h;
    sum2 += double(h) * h;
  }
  const double mean = sum / n;
  return 4.0 * std::sqrt(sum2 / n - mean * mean);
}

TEST(SeaState, ALongRecordOffshoreHasTheSignificantHeight) {
  // On the sea surface the scene's components make, at an offshore point: in deep open water (every
  // component analytic), and offshore of a beach whose plateau is deep for the spectrum (k h > 4 at
  // the peak: shoaling within 1 %), where every component is traced.
  for (double gamma : {1.0, 3.3}) {
    houle::SeaState s;
    s.significant_height = 2.0;
    s.peak_period = 8.0;
    s.gamma = gamma;
    auto scene = houle::validate(open_sea(s));
    ASSERT_TRUE(scene.ok());
    const double hs = record_hs(scene.value(), 200.0f, 200.0f);
    EXPECT_NEAR(hs / 2.0, 1.0, 0.05) << "gamma " << gamma << ": Hs " << hs;
  }
  houle::SeaState s;
  s.significant_height = 1.2;
  s.peak_period = 6.0;
  s.components = 16;
  houle::Scene beach = open_sea(s);
  beach.domain = {0.0, 0.0, 200.0, 200.0};
  beach.floor.base.kind = houle::FloorKind::planar_beach;
  beach.floor.base.depth = 60.0;
  beach.floor.base.slope = 0.3;
  beach.floor.base.shoreline = {0.0, 190.0};
  beach.dwt.step = 1.0;
  beach.dwt.insertion_distance = 2.0;
  auto scene = houle::validate(beach);
  ASSERT_TRUE(scene.ok()) << scene.error().field << ": " << scene.error().message;
  for (std::size_t t = 0; t < scene->trains.size(); ++t) ASSERT_TRUE(houle::train_needs_rays(scene.value(), t));
  const double hs = record_hs(scene.value(), 100.0f, 40.0f);
  EXPECT_NEAR(hs / 1.2, 1.0, 0.05) << "traced: Hs " << hs;
}

}  // namespace
