// Where the waves break, for the renderer's foam (sea_surface.hpp surf_map, docs/rendering.md 3.7).
#include <algorithm>
#include <cmath>

#include "houle/sim/sea_surface.hpp"

namespace houle {
namespace {

// Foam lines a wall's toe out to toe_reach m from its face where the waves there reach
// crash_amplitude m (all of a train's fields summed: incident, diffracted, reflected), less below.
constexpr double toe_reach = 2.5, crash_amplitude = 0.25;

double segment_distance(double px, double py, Point2 a, Point2 b) {
  const double dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
  const double u = len2 > 0.0 ? std::clamp(((px - a.x) * dx + (py - a.y) * dy) / len2, 0.0, 1.0) : 0.0;
  return std::hypot(px - (a.x + u * dx), py - (a.y + u * dy));
}

}  // namespace

SurfMap SeaSurface::surf_map(const Scene& scene) const {
  // The traced trains share the domain's resampling grid; analytic trains never break here.
  std::size_t first = trains_.size();
  for (std::size_t t = 0; t < trains_.size() && first == trains_.size(); ++t) {
    if (!trains_[t].breaking.empty()) first = t;
  }
  if (first == trains_.size()) return {};
  const TrainGrid& g = grids_[first];
  const std::size_t nodes = std::size_t(g.nx) * g.ny;
  SurfMap m;
  m.origin_x = g.origin_x;
  m.origin_y = g.origin_y;
  m.cell = g.cell;
  m.nx = g.nx;
  m.ny = g.ny;
  for (std::vector<float>* v : {&m.foam, &m.dir_x, &m.dir_y, &m.amplitude}) v->assign(nodes, 0.0f);
  std::vector<float> sum(nodes, 0.0f);  // the trains' amplitudes, for the walls
  for (std::size_t t = first; t < trains_.size(); ++t) {
    const TrainField& f = trains_[t];
    if (f.breaking.size() != nodes || grids_[t].nx != g.nx || grids_[t].ny != g.ny) continue;
    for (std::size_t n = 0; n < nodes; ++n) {
      const float a = std::hypot(f.b_re[n], f.b_im[n]), k = std::hypot(f.kx[n], f.ky[n]);
      sum[n] += a;
      if (f.breaking[n] > m.foam[n] && k > 0.0f) {
        m.foam[n] = f.breaking[n];
        m.dir_x[n] = f.kx[n] / k;
        m.dir_y[n] = f.ky[n] / k;
        m.amplitude[n] = a;
      }
    }
  }
  for (const Wall& w : scene.walls) {
    const double reach = 0.5 * w.thickness + toe_reach;
    for (std::size_t s = 0; s + 1 < w.points.size(); ++s) {
      const Point2 a = w.points[s], b = w.points[s + 1];
      const auto index = [&](double v, double origin, std::uint32_t count) {
        return std::size_t(std::clamp(std::floor((v - origin) / double(g.cell)), 0.0, double(count - 1)));
      };
      const std::size_t i0 = index(std::min(a.x, b.x) - reach, g.origin_x, g.nx), i1 = index(std::max(a.x, b.x) + reach, g.origin_x, g.nx) + 1;
      const std::size_t j0 = index(std::min(a.y, b.y) - reach, g.origin_y, g.ny), j1 = index(std::max(a.y, b.y) + reach, g.origin_y, g.ny) + 1;
      for (std::size_t j = j0; j <= std::min(j1, std::size_t(g.ny) - 1); ++j) {
        for (std::size_t i = i0; i <= std::min(i1, std::size_t(g.nx) - 1); ++i) {
          const std::size_t n = j * g.nx + i;
          const double d = segment_distance(g.origin_x + double(i) * g.cell, g.origin_y + double(j) * g.cell, a, b) - 0.5 * w.thickness;
          if (!(d < toe_reach) || !(sum[n] > 0.0f)) continue;
          const double u = std::clamp(1.0 - d / toe_reach, 0.0, 1.0);
          const float foam = float(u * u * (3.0 - 2.0 * u) * std::min(1.0, double(sum[n]) / crash_amplitude));
          if (foam > m.foam[n]) {
            m.foam[n] = foam;
            m.dir_x[n] = m.dir_y[n] = 0.0f;
            m.amplitude[n] = sum[n];
          }
        }
      }
    }
  }
  if (!(*std::max_element(m.foam.begin(), m.foam.end()) > 0.0f)) return {};
  return m;
}

}  // namespace houle
