#include "houle/sim/camera_path.hpp"

#include <algorithm>
#include <array>
#include <numbers>

namespace houle {
namespace {

using Values = std::array<double, 7>;  // position, look_at, field of view

Values values(const ViewCamera& c, std::size_t j) {
  const CameraKey& k = c.keys[j];
  return {k.position.x, k.position.y, k.position.z, k.look_at.x, k.look_at.y, k.look_at.z,
          k.vertical_fov_deg.value_or(c.vertical_fov_deg)};
}

CameraPose pose(const Values& v) { return {{v[0], v[1], v[2]}, {v[3], v[4], v[5]}, v[6]}; }

/// Catmull-Rom tangent (per second) of every value at key j: one-sided at the ends.
Values tangent(const ViewCamera& c, std::size_t j) {
  const std::size_t a = j == 0 ? 0 : j - 1, b = j + 1 == c.keys.size() ? j : j + 1;
  const Values va = values(c, a), vb = values(c, b);
  const double dt = c.keys[b].time - c.keys[a].time;
  Values m{};
  for (std::size_t q = 0; q < m.size(); ++q) m[q] = (vb[q] - va[q]) / dt;
  return m;
}

}  // namespace

CameraPose camera_pose(const ViewCamera& c, double t) noexcept {
  const std::vector<CameraKey>& k = c.keys;
  if (k.empty()) return {c.position, c.look_at, c.vertical_fov_deg};
  if (!(t > k.front().time)) return pose(values(c, 0));  // NaN too
  if (!(t < k.back().time)) return pose(values(c, k.size() - 1));
  // The segment [k[i].time, k[i + 1].time) holding t.
  const auto after = std::upper_bound(k.begin(), k.end(), t, [](double v, const CameraKey& key) { return v < key.time; });
  const std::size_t i = std::size_t(after - k.begin()) - 1;
  const double h = k[i + 1].time - k[i].time, s = (t - k[i].time) / h, s2 = s * s, s3 = s2 * s;
  const double h00 = 2.0 * s3 - 3.0 * s2 + 1.0, h10 = s3 - 2.0 * s2 + s, h01 = 3.0 * s2 - 2.0 * s3, h11 = s3 - s2;
  const Values v0 = values(c, i), v1 = values(c, i + 1), m0 = tangent(c, i), m1 = tangent(c, i + 1);
  Values v{};
  for (std::size_t q = 0; q < v.size(); ++q) v[q] = h00 * v0[q] + h10 * h * m0[q] + h01 * v1[q] + h11 * h * m1[q];
  v[6] = std::clamp(v[6], std::min(v0[6], v1[6]), std::max(v0[6], v1[6]));
  return pose(v);
}

CameraParams camera_params(const CameraPose& p, std::uint32_t width, std::uint32_t height) noexcept {
  CameraParams cp;
  cp.position = {float(p.position.x), float(p.position.y), float(p.position.z)};
  cp.look_at = {float(p.look_at.x), float(p.look_at.y), float(p.look_at.z)};
  cp.vertical_fov = float(p.vertical_fov_deg * std::numbers::pi / 180.0);
  cp.width = width;
  cp.height = height;
  return cp;
}

}  // namespace houle
