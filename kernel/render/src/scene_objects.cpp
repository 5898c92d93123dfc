#include "scene_objects.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace houle::detail {
namespace {

constexpr double inf = std::numeric_limits<double>::infinity();
/// No query walks further than this (m) or more blocks of its first level than this: a guard for rays that graze a level
/// floor for ever, not a limit any real view reaches.
constexpr double max_walk_distance = 1e7;
constexpr std::int64_t max_start_steps = std::int64_t(1) << 18;

bool finite3(const std::array<float, 3>& v) {
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}
bool reflectance_ok(LinearRgb c) {
  const auto ok = [](float x) { return x >= 0.0f && x <= 1.0f; };  // false for NaN
  return ok(c.r) && ok(c.g) && ok(c.b);
}

/// A ray's reciprocal direction, computed once per floor query (+-inf along an axis it does not move).
struct WalkRay {
  const SceneRay& r;
  double inv_dx, inv_dy;
};

/// Amanatides-Woo walk over the square cells of size `size` (1 / size = inv_size) whose corner (0, 0)
/// is (gx, gy), from t0 to t1 along the ray's xy projection: visit(i, j, t_enter, t_exit) for each cell
/// in order of t until it returns true (then true) or t1 is passed (false). Cells are unbounded
/// integers: callers clamp.
template <class Visit>
bool walk_cells(double gx, double gy, double size, double inv_size, const WalkRay& w, double t0, double t1,
                std::int64_t max_steps, Visit&& visit) {
  const SceneRay& r = w.r;
  const double px = r.ox + t0 * r.dx - gx, py = r.oy + t0 * r.dy - gy;
  constexpr double index_limit = 4.0e15;  // keeps the integer conversion defined for absurd inputs
  std::int64_t i = std::int64_t(std::clamp(std::floor(px * inv_size), -index_limit, index_limit));
  std::int64_t j = std::int64_t(std::clamp(std::floor(py * inv_size), -index_limit, index_limit));
  const std::int64_t si = r.dx > 0.0 ? 1 : -1, sj = r.dy > 0.0 ? 1 : -1;
  const double step_x = size * std::abs(w.inv_dx), step_y = size * std::abs(w.inv_dy);
  double next_x = r.dx > 0.0   ? t0 + (double(i + 1) * size - px) * w.inv_dx
                  : r.dx < 0.0 ? t0 + (double(i) * size - px) * w.inv_dx
                               : inf;
  double next_y = r.dy > 0.0   ? t0 + (double(j + 1) * size - py) * w.inv_dy
                  : r.dy < 0.0 ? t0 + (double(j) * size - py) * w.inv_dy
                               : inf;
  double t = t0;
  for (std::int64_t n = 0; n < max_steps; ++n) {
    const double t_exit = std::min(std::min(next_x, next_y), t1);
    if (visit(i, j, t, std::max(t_exit, t))) return true;
    if (t_exit >= t1) return false;
    if (next_x <= next_y) {
      i += si;
      t = next_x;
      next_x += step_x;
    } else {
      j += sj;
      t = next_y;
      next_y += step_y;
    }
  }
  return false;
}

}  // namespace

Expected<SceneObjects> SceneObjects::build(const RenderScene& scene) {
  SceneObjects s;
  for (std::size_t k = 0; k < scene.boxes.size(); ++k) {
    const RenderBox& b = scene.boxes[k];
    const std::string field = "boxes[" + std::to_string(k) + "]";
    if (!finite3(b.center)) return Error{field + ".center", "three finite coordinates in m"};
    if (!finite3(b.half_extent) || !(b.half_extent[0] > 0.0f && b.half_extent[1] > 0.0f && b.half_extent[2] > 0.0f)) {
      return Error{field + ".half_extent", "three finite lengths > 0 in m"};
    }
    if (!std::isfinite(b.yaw_rad)) return Error{field + ".yaw_rad", "a finite angle in rad"};
    if (!reflectance_ok(b.colour)) return Error{field + ".colour", "a diffuse reflectance, each channel in [0, 1]"};
    if (!(std::isfinite(b.motion) && b.motion >= 0.0f)) return Error{field + ".motion", "a finite length >= 0 in m"};
    const double c = std::cos(double(b.yaw_rad)), sn = std::sin(double(b.yaw_rad));
    s.boxes_.push_back({b.center[0], b.center[1], b.center[2], b.half_extent[0], b.half_extent[1], b.half_extent[2],
                        {{c, sn, 0.0}, {-sn, c, 0.0}, {0.0, 0.0, 1.0}}, b.colour,
                        s.add_mover(b.center, b.motion, double(b.half_extent[0]) + b.half_extent[1] + b.half_extent[2])});
  }
  for (std::size_t k = 0; k < scene.spheres.size(); ++k) {
    const RenderSphere& sp = scene.spheres[k];
    const std::string field = "spheres[" + std::to_string(k) + "]";
    if (!finite3(sp.center)) return Error{field + ".center", "three finite coordinates in m"};
    if (!(std::isfinite(sp.radius) && sp.radius > 0.0f)) return Error{field + ".radius", "a finite length > 0 in m"};
    if (!reflectance_ok(sp.colour)) return Error{field + ".colour", "a diffuse reflectance, each channel in [0, 1]"};
    if (!(std::isfinite(sp.motion) && sp.motion >= 0.0f)) return Error{field + ".motion", "a finite length >= 0 in m"};
    s.spheres_.push_back({sp.center[0], sp.center[1], sp.center[2], sp.radius, sp.colour, s.add_mover(sp.center, sp.motion, sp.radius)});
  }

  s.build_bvh();

  const FloorGrid& f = scene.floor;
  if (!reflectance_ok(f.sand)) return Error{"floor.sand", "a diffuse reflectance, each channel in [0, 1]"};
  s.sand_ = f.sand;
  if (f.nx == 0 && f.ny == 0) {
    if (!f.z.empty()) return Error{"floor.z", "no samples when nx = ny = 0 (no floor)"};
    return s;
  }
  constexpr std::uint32_t max_side = 1u << 16;
  if (f.nx == 0 || f.ny == 0 || f.nx > max_side || f.ny > max_side) {
    return Error{"floor.nx", "nx and ny both in [1, 65536], or both 0 for no floor"};
  }
  if (!(std::isfinite(f.cell) && f.cell > 0.0f)) return Error{"floor.cell", "a finite cell size > 0 in m"};
  if (!std::isfinite(f.origin_x) || !std::isfinite(f.origin_y)) return Error{"floor.origin", "finite coordinates in m"};
  if (f.z.size() != std::size_t(f.nx) * f.ny) return Error{"floor.z", "nx * ny heights"};
  for (float z : f.z) {
    if (!std::isfinite(z)) return Error{"floor.z", "finite heights in m"};
  }
  s.origin_x_ = f.origin_x;
  s.origin_y_ = f.origin_y;
  s.cell_ = f.cell;
  s.nx_ = f.nx;
  s.ny_ = f.ny;
  s.z_ = f.z;
  const auto [lo, hi] = std::minmax_element(f.z.begin(), f.z.end());
  s.z_min_ = *lo;
  s.z_max_ = *hi;
  constexpr std::int64_t B = block_cells;
  for (int k = 0; k < max_levels; ++k) {
    s.level_size_[k] = k == 0 ? double(f.cell) : s.level_size_[k - 1] * double(B);
    s.level_inv_size_[k] = 1.0 / s.level_size_[k];
  }
  s.levels_ = 1;
  s.level_nx_[0] = std::max<std::int64_t>(1, s.nx_ - 1);  // cells
  s.level_ny_[0] = std::max<std::int64_t>(1, s.ny_ - 1);
  while (s.levels_ < max_levels && (s.level_nx_[s.levels_ - 1] > 1 || s.level_ny_[s.levels_ - 1] > 1)) {
    const int k = s.levels_++;
    const std::int64_t bx = (s.level_nx_[k - 1] + B - 1) / B, by = (s.level_ny_[k - 1] + B - 1) / B;
    s.level_nx_[k] = bx;
    s.level_ny_[k] = by;
    std::vector<float>& m = s.level_max_[k];
    m.assign(std::size_t(bx * by), -std::numeric_limits<float>::infinity());
    for (std::int64_t bj = 0; bj < by; ++bj) {
      for (std::int64_t bi = 0; bi < bx; ++bi) {
        float mx = -std::numeric_limits<float>::infinity();
        if (k == 1) {
          for (std::int64_t j = bj * B; j <= std::min(bj * B + B, s.ny_ - 1); ++j) {
            for (std::int64_t i = bi * B; i <= std::min(bi * B + B, s.nx_ - 1); ++i) {
              mx = std::max(mx, s.z_[std::size_t(j * s.nx_ + i)]);
            }
          }
        } else {
          const std::vector<float>& c = s.level_max_[k - 1];
          const std::int64_t cx = s.level_nx_[k - 1], cy = s.level_ny_[k - 1];
          for (std::int64_t j = bj * B; j < std::min(bj * B + B, cy); ++j) {
            for (std::int64_t i = bi * B; i < std::min(bi * B + B, cx); ++i) mx = std::max(mx, c[std::size_t(j * cx + i)]);
          }
        }
        m[std::size_t(bj * bx + bi)] = mx;
      }
    }
  }
  s.build_clearance();
  s.build_floor_grid();
  return s;
}

void SceneObjects::build_floor_grid() {
  const std::int64_t wx = nx_ + 2, wy = ny_ + 2;  // samples -1 .. n
  if (wx * wy > std::numeric_limits<std::int32_t>::max()) return;  // floor_grid() then says too_large
  grid_z_.resize(std::size_t(wx * wy));
  for (std::int64_t j = 0; j < wy; ++j) {
    for (std::int64_t i = 0; i < wx; ++i) grid_z_[std::size_t(j * wx + i)] = sample(i - 1, j - 1);
  }
  grid_cell_max_.resize(std::size_t((wx - 1) * (wy - 1)));  // cells -1 .. n - 1
  for (std::int64_t j = 0; j + 1 < wy; ++j) {
    for (std::int64_t i = 0; i + 1 < wx; ++i) {
      const float* p = &grid_z_[std::size_t(j * wx + i)];
      grid_cell_max_[std::size_t(j * (wx - 1) + i)] = std::max(std::max(p[0], p[1]), std::max(p[wx], p[wx + 1]));
    }
  }
  // The bands (FloorBand): heights evenly from the lowest cell maximum to the highest (rising with the
  // index, so a cell reaches the bands up to one), each band's box in cells (-1 .. n - 1, the border
  // cells at the ends) and then in metres. One pass: each cell goes into the box of the highest band
  // it reaches, then every box takes in the boxes above it.
  const auto [lo, hi] = std::minmax_element(grid_cell_max_.begin(), grid_cell_max_.end());
  for (int k = 0; k < floor_bands; ++k) bands_[std::size_t(k)].z = *lo + (*hi - *lo) * float(k) / float(floor_bands);
  const std::int64_t cx = wx - 1, cy = wy - 1;
  struct Cells {
    std::int64_t i0, i1, j0, j1;
  };
  std::array<Cells, floor_bands> boxes;
  boxes.fill({cx, -1, cy, -1});  // empty
  for (std::int64_t j = 0; j < cy; ++j) {
    for (std::int64_t i = 0; i < cx; ++i) {
      const float m = grid_cell_max_[std::size_t(j * cx + i)];
      if (!(m >= bands_[0].z)) continue;
      std::size_t k = 0;
      while (k + 1 < floor_bands && m >= bands_[k + 1].z) ++k;
      Cells& c = boxes[k];
      c.i0 = std::min(c.i0, i), c.i1 = std::max(c.i1, i), c.j0 = std::min(c.j0, j), c.j1 = std::max(c.j1, j);
    }
  }
  for (std::size_t k = floor_bands - 1; k-- > 0;) {
    const Cells& up = boxes[k + 1];
    Cells& c = boxes[k];
    c = {std::min(c.i0, up.i0), std::max(c.i1, up.i1), std::min(c.j0, up.j0), std::max(c.j1, up.j1)};
  }
  // Cell c (array index c, grid cell c - 1) spans [origin + (c - 1) cell, origin + c cell].
  const auto edge = [&](std::int64_t c, double origin, bool border, float beyond) {
    return border ? beyond : float(origin + double(c - 1) * cell_);
  };
  for (std::size_t k = 0; k < floor_bands; ++k) {
    const Cells& c = boxes[k];
    FloorBand& b = bands_[k];
    b.x0 = edge(c.i0 - 1, origin_x_, c.i0 == 0, -float(inf));
    b.x1 = edge(c.i1 + 2, origin_x_, c.i1 == cx - 1, float(inf));
    b.y0 = edge(c.j0 - 1, origin_y_, c.j0 == 0, -float(inf));
    b.y1 = edge(c.j1 + 2, origin_y_, c.j1 == cy - 1, float(inf));
  }
}

FloorGridView SceneObjects::floor_grid() const noexcept {
  if (grid_z_.empty()) {
    FloorGridView none;
    none.too_large = nx_ > 0;
    return none;
  }
  constexpr float below = 1e-3f;  // as floor_span's range
  FloorGridView v{grid_z_.data(), grid_cell_max_.data(), float(origin_x_), float(origin_y_), float(cell_), float(1.0 / cell_),
                  std::int32_t(nx_), std::int32_t(ny_), float(z_min_) - below, float(z_max_)};
  std::copy(bands_.begin(), bands_.end(), v.bands);
  return v;
}

void SceneObjects::build_clearance() {
  // Per cell, the highest sample of the cells within clear_cells of it in each axis: the maximum of
  // the cells' corner maxima over a (2 clear_cells + 1)^2 window, separably (rows, then columns).
  const std::int64_t cx = level_nx_[0], cy = level_ny_[0];
  std::vector<float>& corner = level_max_[0];
  corner.resize(std::size_t(cx * cy));
  std::vector<float> rows(corner.size());
  for (std::int64_t j = 0; j < cy; ++j) {
    for (std::int64_t i = 0; i < cx; ++i) {
      corner[std::size_t(j * cx + i)] =
          std::max(std::max(sample(i, j), sample(i + 1, j)), std::max(sample(i, j + 1), sample(i + 1, j + 1)));
    }
  }
  const auto window_max = [](const float* p, std::int64_t n, std::int64_t step, std::int64_t at) {
    constexpr std::int64_t k = clear_cells;
    float m = -std::numeric_limits<float>::infinity();
    for (std::int64_t a = std::max<std::int64_t>(0, at - k); a <= std::min(n - 1, at + k); ++a) m = std::max(m, p[a * step]);
    return m;
  };
  for (std::int64_t j = 0; j < cy; ++j) {
    for (std::int64_t i = 0; i < cx; ++i) rows[std::size_t(j * cx + i)] = window_max(&corner[std::size_t(j * cx)], cx, 1, i);
  }
  clear_max_.resize(corner.size());
  for (std::int64_t j = 0; j < cy; ++j) {
    for (std::int64_t i = 0; i < cx; ++i) clear_max_[std::size_t(j * cx + i)] = window_max(&rows[std::size_t(i)], cy, cx, j);
  }
}

double SceneObjects::clear_until(const SceneRay& r, double t0, double t1) const noexcept {
  // From a point in cell c (clamped to the grid: the extended edges repeat the edge samples, and
  // clamping moves no two points further apart), every point within clear_cells cells in each axis
  // lies in c's window, so the floor there is at most clear_max_[c]. The ray stays that close while it
  // moves clear_cells cells along its faster horizontal axis (less a hundredth of a cell, for the
  // rounding of the cell's index), and, as it does not descend, cannot meet the floor there while it
  // starts above that maximum (plus a margin far beyond the walk's rounding).
  constexpr double margin = 1e-4;  // m
  constexpr int max_jumps = 4;
  const double speed = std::max(std::abs(r.dx), std::abs(r.dy));
  const double reach = (double(clear_cells) - 0.01) * cell_ / speed;  // +inf for a vertical ray
  const double inv_cell = level_inv_size_[0], last_i = double(level_nx_[0] - 1), last_j = double(level_ny_[0] - 1);
  double t = t0;
  for (int n = 0; n < max_jumps && t < t1; ++n) {
    const double fx = (r.ox + t * r.dx - origin_x_) * inv_cell, fy = (r.oy + t * r.dy - origin_y_) * inv_cell;
    // Clamped (NaN to 0: the z test below stops a NaN ray, which the walk then handles as before).
    const auto i = std::size_t(fx > 0.0 ? (fx < last_i ? fx : last_i) : 0.0);
    const auto j = std::size_t(fy > 0.0 ? (fy < last_j ? fy : last_j) : 0.0);
    const double top = double(clear_max_[j * std::size_t(level_nx_[0]) + i]) + margin;
    if (!(r.oz + t * r.dz > top)) break;
    if (!(t + reach > t)) break;
    t += reach;
  }
  return std::min(t, t1);
}

void SceneObjects::build_bvh() {
  // Bounds of every primitive (the yawed box's footprint, a sphere's cube), widened a little so that
  // float bounds stay conservative for the double tests.
  struct Prim {
    std::uint32_t id;
    float lo[3], hi[3], centre[3];
  };
  std::vector<Prim> prims;
  const auto add = [&](std::uint32_t id, double cx, double cy, double cz, double ex, double ey, double ez) {
    Prim p{id, {}, {}, {}};
    const double c[3] = {cx, cy, cz}, e[3] = {ex, ey, ez};
    for (int a = 0; a < 3; ++a) {
      const double pad = 1e-4 * (std::abs(c[a]) + e[a]) + 1e-4;
      p.lo[a] = float(c[a] - e[a] - pad);
      p.hi[a] = float(c[a] + e[a] + pad);
      p.centre[a] = float(c[a]);
    }
    prims.push_back(p);
  };
  // A moving object: everywhere it may go, in any orientation.
  for (std::size_t k = 0; k < boxes_.size(); ++k) {
    const Box& b = boxes_[k];
    if (b.mover >= 0) {
      const Mover& m = movers_[std::size_t(b.mover)];
      const double reach = m.hi[0] - m.rest[0];
      add(std::uint32_t(k), b.cx, b.cy, b.cz, reach, reach, reach);
      continue;
    }
    const double ac = std::abs(b.axes[0][0]), as = std::abs(b.axes[0][1]);
    add(std::uint32_t(k), b.cx, b.cy, b.cz, ac * b.hx + as * b.hy, as * b.hx + ac * b.hy, b.hz);
  }
  for (std::size_t k = 0; k < spheres_.size(); ++k) {
    const Sphere& sp = spheres_[k];
    const double reach = sp.mover >= 0 ? movers_[std::size_t(sp.mover)].hi[0] - movers_[std::size_t(sp.mover)].rest[0] : sp.radius;
    add(std::uint32_t(k) | sphere_bit, sp.cx, sp.cy, sp.cz, reach, reach, reach);
  }
  nodes_.clear();
  primitives_.clear();
  if (prims.empty()) return;
  // Median split on the longest axis of the centres, a primitive per leaf (a leaf of two could hold a
  // block of each of two walls far apart, and its box the water between them: cut_bounds and the
  // walk would send rays there): the tree's depth is log2 of the count, far below max_bvh_depth for
  // any scene that fits in memory.
  nodes_.reserve(2 * prims.size());
  struct Task {
    std::uint32_t node, begin, end;
  };
  std::vector<Task> todo{{0, 0, std::uint32_t(prims.size())}};
  nodes_.push_back({});
  while (!todo.empty()) {
    const Task t = todo.back();
    todo.pop_back();
    Node nd;
    float clo[3] = {std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
                    std::numeric_limits<float>::infinity()};
    float chi[3] = {-clo[0], -clo[1], -clo[2]};
    for (int a = 0; a < 3; ++a) nd.lo[a] = clo[a], nd.hi[a] = chi[a];
    for (std::uint32_t k = t.begin; k < t.end; ++k) {
      for (int a = 0; a < 3; ++a) {
        nd.lo[a] = std::min(nd.lo[a], prims[k].lo[a]);
        nd.hi[a] = std::max(nd.hi[a], prims[k].hi[a]);
        clo[a] = std::min(clo[a], prims[k].centre[a]);
        chi[a] = std::max(chi[a], prims[k].centre[a]);
      }
    }
    if (t.end - t.begin == 1) {
      nd.first = std::uint32_t(primitives_.size());
      nd.count = t.end - t.begin;
      for (std::uint32_t k = t.begin; k < t.end; ++k) primitives_.push_back(prims[k].id);
    } else {
      int axis = 0;
      for (int a = 1; a < 3; ++a) {
        if (chi[a] - clo[a] > chi[axis] - clo[axis]) axis = a;
      }
      const std::uint32_t mid = t.begin + (t.end - t.begin) / 2;
      std::nth_element(prims.begin() + t.begin, prims.begin() + mid, prims.begin() + t.end,
                       [axis](const Prim& x, const Prim& y) { return x.centre[axis] < y.centre[axis]; });
      nd.first = std::uint32_t(nodes_.size());
      nd.count = 0;
      nodes_.push_back({});
      nodes_.push_back({});
      todo.push_back({nd.first, t.begin, mid});
      todo.push_back({nd.first + 1, mid, t.end});
    }
    nodes_[t.node] = nd;
  }
  cut_bounds();
}

void SceneObjects::cut_bounds() {
  // From the root down, the node of the largest surface area is replaced by its two children while
  // they fit: the rays a box lets through grow with its area.
  const auto area = [&](std::uint32_t k) {
    const Node& nd = nodes_[k];
    const double x = double(nd.hi[0]) - nd.lo[0], y = double(nd.hi[1]) - nd.lo[1], z = double(nd.hi[2]) - nd.lo[2];
    return x * y + y * z + z * x;
  };
  bounds_ = {};
  if (nodes_.empty()) return;
  std::vector<std::uint32_t> cut{0};
  while (cut.size() < std::size_t(max_object_bounds)) {
    std::size_t widest = cut.size();
    for (std::size_t i = 0; i < cut.size(); ++i) {
      if (nodes_[cut[i]].count == 0 && (widest == cut.size() || area(cut[i]) > area(cut[widest]))) widest = i;
    }
    if (widest == cut.size()) break;  // only leaves
    const std::uint32_t first = nodes_[cut[widest]].first;
    cut[widest] = first;
    cut.push_back(first + 1);
  }
  bounds_.count = int(cut.size());
  std::copy_n(nodes_[0].lo, 3, bounds_.all_lo);
  std::copy_n(nodes_[0].hi, 3, bounds_.all_hi);
  for (std::size_t i = 0; i < cut.size(); ++i) {
    std::copy_n(nodes_[cut[i]].lo, 3, bounds_.lo[i]);
    std::copy_n(nodes_[cut[i]].hi, 3, bounds_.hi[i]);
    cut_nodes_[i] = cut[i];
  }
}

float SceneObjects::sample(std::int64_t i, std::int64_t j) const noexcept {
  i = std::clamp<std::int64_t>(i, 0, nx_ - 1);
  j = std::clamp<std::int64_t>(j, 0, ny_ - 1);
  return z_[std::size_t(j * nx_ + i)];
}

double SceneObjects::floor_height(double x, double y) const noexcept {
  if (nx_ == 0) return -inf;
  const double fx = (x - origin_x_) / cell_, fy = (y - origin_y_) / cell_;
  if (!std::isfinite(fx) || !std::isfinite(fy)) return z_min_;
  const double cx = std::clamp(fx, -1.0, double(nx_)), cy = std::clamp(fy, -1.0, double(ny_));
  const double fi = std::floor(cx), fj = std::floor(cy);
  const double u = cx - fi, v = cy - fj;
  const auto i = std::int64_t(fi), j = std::int64_t(fj);
  const double h00 = sample(i, j), h10 = sample(i + 1, j), h01 = sample(i, j + 1), h11 = sample(i + 1, j + 1);
  return h00 + (h10 - h00) * u + (h01 - h00) * v + (h00 - h10 - h01 + h11) * u * v;
}

struct SceneObjects::FloorQuery {
  WalkRay w;
  double t_hit;                   // t_max until a hit
  std::array<float, 3>* normal;  // written on a hit when not null
};

SceneObjects::FloorSpan SceneObjects::floor_span(const SceneRay& r, double t_min, double t_max) const noexcept {
  constexpr FloorSpan none{0.0, 0.0, 0, false};
  if (nx_ == 0) return none;
  // Only where the ray is inside the floor's height range can it meet the floor. The
  // range reaches a little below the lowest ground: a ray meeting ground that lies at that height (the
  // flat extension beyond the deepest edge) meets it at the span's very end, where rounding would
  // keep or drop the root from one ray to the next.
  constexpr double below = 1e-3;  // m
  const double lo = z_min_ - below, hi = z_max_;
  double t0 = t_min, t1 = std::min(t_max, max_walk_distance);
  if (r.dz > 0.0) {
    t0 = std::max(t0, (lo - r.oz) / r.dz);
    t1 = std::min(t1, (hi - r.oz) / r.dz);
  } else if (r.dz < 0.0) {
    t0 = std::max(t0, (hi - r.oz) / r.dz);
    t1 = std::min(t1, (lo - r.oz) / r.dz);
  } else if (r.oz < lo || r.oz > hi) {
    return none;
  }
  if (!(t0 <= t1)) return none;

  return {t0, t1, first_level(r, t0, t1), true};
}

int SceneObjects::first_level(const SceneRay& r, double t0, double t1) const noexcept {
  // The finest level whose blocks the segment crosses only a few of: the levels above would only
  // confirm what this one finds (short refracted and shadow rays go straight to the cells).
  const double horizontal = (t1 - t0) * std::sqrt(r.dx * r.dx + r.dy * r.dy);
  int level = 0;
  for (double size = cell_; level < levels_ - 1 && horizontal > 4.0 * size; size *= block_cells) ++level;
  return level;
}

double SceneObjects::floor_hit(const SceneRay& r, double t_min, double t_max, std::array<float, 3>* normal,
                               bool skip_clear) const noexcept {
  FloorSpan span = floor_span(r, t_min, t_max);
  if (!span.walk) return t_max;
  // Rays that rise (reflected rays, shadows) start low over the ground they clear; rays that descend
  // (refracted) meet the floor within a few cells, where the jumps would cost more than they skip.
  if (skip_clear && !(r.dz < 0.0)) {
    span.t0 = clear_until(r, span.t0, span.t1);
    if (!(span.t0 < span.t1)) return t_max;
    span.level = first_level(r, span.t0, span.t1);
  }
  const double inv_dx = r.dx != 0.0 ? 1.0 / r.dx : inf, inv_dy = r.dy != 0.0 ? 1.0 / r.dy : inf;
  FloorQuery q{{r, inv_dx, inv_dy}, t_max, normal};
  walk_level(span.level, q, span.t0, span.t1, max_start_steps);
  return q.t_hit;
}

bool SceneObjects::walk_level(int level, FloorQuery& q, double ta, double tb, std::int64_t steps) const noexcept {
  const double size = level_size_[level], inv_size = level_inv_size_[level];
  const SceneRay& r = q.w.r;
  // Cells and blocks are visited in order of t, so the first hit is the nearest: shadow rays stop
  // there too. The first level may walk far (rays grazing the extended edges); the ones below cross
  // at most a block of the level above.
  constexpr std::int64_t nested_steps = 2 * block_cells + 8;
  if (level == 0) {
    return walk_cells(origin_x_, origin_y_, size, inv_size, q.w, ta, tb, steps,
                      [&](std::int64_t i, std::int64_t j, double a, double b) { return hit_cell(q, i, j, a, b); });
  }
  const std::vector<float>& m = level_max_[level];
  const std::int64_t bx = level_nx_[level], by = level_ny_[level];
  return walk_cells(origin_x_, origin_y_, size, inv_size, q.w, ta, tb, steps,
                    [&](std::int64_t i, std::int64_t j, double a, double b) {
                      const std::size_t k = std::size_t(std::clamp<std::int64_t>(j, 0, by - 1) * bx +
                                                        std::clamp<std::int64_t>(i, 0, bx - 1));
                      // Passing above the whole block: nothing in it.
                      if (std::min(r.oz + a * r.dz, r.oz + b * r.dz) > double(m[k])) return false;
                      return walk_level(level - 1, q, a, b, nested_steps);
                    });
}

bool SceneObjects::hit_cell(FloorQuery& q, std::int64_t i, std::int64_t j, double ta, double tb) const noexcept {
  const SceneRay& r = q.w.r;
  const double cell = cell_, inv_cell = level_inv_size_[0];
  const double za = r.oz + ta * r.dz, zb = r.oz + tb * r.dz;
  double h00, h10, h01, h11;
  if (i >= 0 && j >= 0 && i < nx_ - 1 && j < ny_ - 1) {
    // Most cells a walk visits it passes above: one load of the cell's highest corner tells.
    if (std::min(za, zb) > double(level_max_[0][std::size_t(j * (nx_ - 1) + i)])) return false;
    const float* p = z_.data() + (j * nx_ + i);
    h00 = p[0], h10 = p[1], h01 = p[nx_], h11 = p[nx_ + 1];
  } else {
    h00 = sample(i, j), h10 = sample(i + 1, j), h01 = sample(i, j + 1), h11 = sample(i + 1, j + 1);
    if (std::min(za, zb) > std::max(std::max(h00, h10), std::max(h01, h11))) return false;
  }
  // Along the ray, s = t - ta: u = u0 + du s, v = v0 + dv s in cell units, and the bilinear
  // h = h00 + e u + f v + g u v becomes a + b s + c s^2; solve z(s) - h(s) = 0.
  const double u0 = (r.ox + ta * r.dx - (origin_x_ + double(i) * cell)) * inv_cell;
  const double v0 = (r.oy + ta * r.dy - (origin_y_ + double(j) * cell)) * inv_cell;
  const double du = r.dx * inv_cell, dv = r.dy * inv_cell;
  const double e = h10 - h00, f = h01 - h00, g = h00 - h10 - h01 + h11;
  const double a = h00 + e * u0 + f * v0 + g * u0 * v0;
  const double b = e * du + f * dv + g * (u0 * dv + v0 * du);
  const double c = g * du * dv;
  const double a0 = za - a;  // height above the ground on entering
  const double s_end = tb - ta;
  double s = inf;
  if (a0 <= 0.0) {
    s = 0.0;  // at or under the ground on entering (a ray starting inside it, or rounding at an edge)
  } else {
    // c s^2 + qb s + qc = 0 with qb = b - dz, qc = -a0 (< 0); the stable pair of roots.
    const double qb = b - r.dz, qc = -a0;
    const double disc = qb * qb - 4.0 * c * qc;
    if (disc >= 0.0) {
      const double qq = -0.5 * (qb + std::copysign(std::sqrt(disc), qb));
      const double r1 = qq != 0.0 ? qc / qq : inf, r2 = c != 0.0 ? qq / c : inf;
      for (double root : {r1, r2}) {
        if (root >= 0.0 && root <= s_end && root < s) s = root;
      }
    }
  }
  if (!(s <= s_end) || !(ta + s < q.t_hit)) return false;
  q.t_hit = ta + s;
  if (q.normal != nullptr) {
    const double u = std::clamp(u0 + du * s, 0.0, 1.0), v = std::clamp(v0 + dv * s, 0.0, 1.0);
    const double gx = (e + g * v) * inv_cell, gy = (f + g * u) * inv_cell;
    const double inv = 1.0 / std::sqrt(gx * gx + gy * gy + 1.0);
    *q.normal = {float(-gx * inv), float(-gy * inv), float(inv)};
  }
  return true;
}

bool SceneObjects::hit_box(std::uint32_t k, const SceneRay& r, double t_min, double& best, SurfaceHit& hit) const noexcept {
  const Box& b = boxes_[k];
  const double px = r.ox - b.cx, py = r.oy - b.cy, pz = r.oz - b.cz;
  // Into the box's frame.
  const auto local = [&](int a, double x, double y, double z) { return b.axes[a][0] * x + b.axes[a][1] * y + b.axes[a][2] * z; };
  const double l[3] = {local(0, px, py, pz), local(1, px, py, pz), local(2, px, py, pz)};
  const double d[3] = {local(0, r.dx, r.dy, r.dz), local(1, r.dx, r.dy, r.dz), local(2, r.dx, r.dy, r.dz)};
  const double h[3] = {b.hx, b.hy, b.hz};
  double t_near = -inf, t_far = inf;
  int axis_near = 0, axis_far = 0;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (std::abs(l[a]) > h[a]) return false;
      continue;
    }
    double t1 = (-h[a] - l[a]) / d[a], t2 = (h[a] - l[a]) / d[a];
    if (t1 > t2) std::swap(t1, t2);
    if (t1 > t_near) t_near = t1, axis_near = a;
    if (t2 < t_far) t_far = t2, axis_far = a;
  }
  if (t_near > t_far) return false;
  // From outside the near face; from inside (a camera in a box) the far face.
  const bool outside = t_near >= t_min;
  const double t = outside ? t_near : t_far;
  if (!(t >= t_min && t < best)) return false;
  const int axis = outside ? axis_near : axis_far;
  const double sign = (d[axis] > 0.0) == outside ? -1.0 : 1.0;
  const double* const e = b.axes[axis];
  const std::array<double, 3> n{e[0] * sign, e[1] * sign, e[2] * sign};
  best = t;
  hit = {float(t), HitKind::box, k, {float(n[0]), float(n[1]), float(n[2])}};
  return true;
}

bool SceneObjects::hit_sphere(std::uint32_t k, const SceneRay& r, double t_min, double& best, SurfaceHit& hit) const noexcept {
  const Sphere& sp = spheres_[k];
  const double px = r.ox - sp.cx, py = r.oy - sp.cy, pz = r.oz - sp.cz;
  const double b = px * r.dx + py * r.dy + pz * r.dz;
  const double c = px * px + py * py + pz * pz - sp.radius * sp.radius;
  const double disc = b * b - c;
  if (!(disc >= 0.0)) return false;
  const double q = std::sqrt(disc);
  double t = -b - q;
  if (t < t_min) t = -b + q;
  if (!(t >= t_min && t < best)) return false;
  const double inv = 1.0 / sp.radius;
  best = t;
  hit = {float(t), HitKind::sphere, k,
         {float((px + t * r.dx) * inv), float((py + t * r.dy) * inv), float((pz + t * r.dz) * inv)}};
  return true;
}

SurfaceHit SceneObjects::hit_objects(const SceneRay& r, double t_min, double t_max, bool any, std::uint32_t cut) const noexcept {
  SurfaceHit hit;
  if (nodes_.empty()) return hit;
  double best = t_max;
  const double inv[3] = {1.0 / r.dx, 1.0 / r.dy, 1.0 / r.dz};  // +-inf on an axis the ray does not move along
  const double o[3] = {r.ox, r.oy, r.oz};
  // Entry distance of the ray into a node's box within [t_min, best], or +inf.
  const auto enter = [&](const Node& nd) {
    double t0 = t_min, t1 = best;
    for (int a = 0; a < 3; ++a) {
      double ta = (double(nd.lo[a]) - o[a]) * inv[a], tb = (double(nd.hi[a]) - o[a]) * inv[a];
      if (ta > tb) std::swap(ta, tb);
      // A ray parallel to a slab gives NaN (0 * inf) on its plane: the max/min below ignore it. With a
      // direction of -0 on that axis the other plane's infinity then drops the node, which loses nothing:
      // every box lies strictly inside its node's padded bounds, so a ray on a node's face meets none.
      t0 = ta > t0 ? ta : t0;
      t1 = tb < t1 ? tb : t1;
    }
    return t0 <= t1 ? t0 : inf;
  };
  // Room for the cut's boxes as well as for a walk down from any of them.
  std::uint32_t stack[max_bvh_depth + max_object_bounds];
  int top = 0;
  if (cut == 0) {
    if (enter(nodes_[0]) == inf) return hit;
    stack[top++] = 0;
  } else {
    // The cut's boxes the ray meets, the nearest on top: its walk shrinks `best` for the others.
    double entry[max_object_bounds];
    for (int i = 0; i < bounds_.count; ++i) {
      if ((cut >> i & 1u) == 0) continue;
      const double t = enter(nodes_[cut_nodes_[i]]);
      if (t == inf) continue;
      int k = top++;
      for (; k > 0 && entry[k - 1] < t; --k) entry[k] = entry[k - 1], stack[k] = stack[k - 1];
      entry[k] = t;
      stack[k] = cut_nodes_[i];
    }
  }
  while (top > 0) {
    const Node& nd = nodes_[stack[--top]];
    if (nd.count > 0) {
      for (std::uint32_t k = nd.first; k < nd.first + nd.count; ++k) {
        const std::uint32_t id = primitives_[k];
        const bool found = id & sphere_bit ? hit_sphere(id & ~sphere_bit, r, t_min, best, hit)
                                           : hit_box(id, r, t_min, best, hit);
        if (found && any) return hit;
      }
      continue;
    }
    // Visit the nearer child first: the farther one is often culled by the shrunken `best` then.
    const std::uint32_t a = nd.first, b = nd.first + 1;
    const double ta = enter(nodes_[a]), tb = enter(nodes_[b]);
    if (top + 2 > max_bvh_depth + max_object_bounds) break;  // cannot happen: the median split's depth is log2 of the count
    if (ta <= tb) {
      if (tb != inf) stack[top++] = b;
      if (ta != inf) stack[top++] = a;
    } else {
      if (ta != inf) stack[top++] = a;
      if (tb != inf) stack[top++] = b;
    }
  }
  return hit;
}

SurfaceHit SceneObjects::nearest(const SceneRay& r, double t_min, double t_max, bool skip_clear) const noexcept {
  SurfaceHit hit = hit_objects(r, t_min, t_max);
  const double best = hit.kind == HitKind::none ? t_max : double(hit.t);
  std::array<float, 3> n{};
  const double tf = floor_hit(r, t_min, best, &n, skip_clear);
  if (tf < best) hit = {float(tf), HitKind::floor, 0, n};
  return hit;
}

SurfaceHit SceneObjects::intersect(const SceneRay& r, double t_min, double t_max) const noexcept {
  return nearest(r, t_min, t_max, false);
}

SurfaceHit SceneObjects::intersect_secondary(const SceneRay& r, double t_min, double t_max) const noexcept {
  return nearest(r, t_min, t_max, true);
}

bool SceneObjects::meets_movers(const SceneRay& r, double t_max) const noexcept {
  const double inv[3] = {1.0 / r.dx, 1.0 / r.dy, 1.0 / r.dz};
  const double o[3] = {r.ox, r.oy, r.oz};
  for (const Mover& m : movers_) {
    double t0 = 0.0, t1 = t_max;
    for (int a = 0; a < 3; ++a) {
      double ta = (m.lo[a] - o[a]) * inv[a], tb = (m.hi[a] - o[a]) * inv[a];
      if (ta > tb) std::swap(ta, tb);
      // NaN (a ray parallel to a slab, on its plane) is ignored, as in hit_objects; a -0 direction
      // then drops the bounds, and rightly: they are padded beyond the object (set_bounds).
      t0 = ta > t0 ? ta : t0;
      t1 = tb < t1 ? tb : t1;
    }
    if (t0 <= t1) return true;
  }
  return false;
}

std::int32_t SceneObjects::add_mover(const std::array<float, 3>& center, float motion, double reach) {
  if (!(motion > 0.0f)) return -1;
  Mover m{{center[0], center[1], center[2]}, motion, {}, {}};
  for (int a = 0; a < 3; ++a) {
    m.lo[a] = m.rest[a] - reach - m.motion;
    m.hi[a] = m.rest[a] + reach + m.motion;
  }
  movers_.push_back(m);
  return std::int32_t(movers_.size() - 1);
}

namespace {
// The centre clamped to within `motion` of `rest` on each axis, from float coordinates.
void clamp_centre(const std::array<float, 3>& c, const double (&rest)[3], double motion, double& x, double& y, double& z) {
  const auto clamp = [&](float v, int a) {
    return std::isfinite(v) ? std::clamp(double(v), rest[a] - motion, rest[a] + motion) : rest[a];
  };
  x = clamp(c[0], 0), y = clamp(c[1], 1), z = clamp(c[2], 2);
}
// The present bounds: `reach` from the centre on each axis, widened far beyond double rounding so
// that no ray the exact tests find meeting the object is said to miss them.
void set_bounds(double (&lo)[3], double (&hi)[3], const double (&centre)[3], const double (&reach)[3]) {
  for (int c = 0; c < 3; ++c) {
    const double pad = 1e-6 * (std::abs(centre[c]) + reach[c]);
    lo[c] = centre[c] - reach[c] - pad;
    hi[c] = centre[c] + reach[c] + pad;
  }
}
}  // namespace

void SceneObjects::move_box(std::size_t k, const BoxPose& pose) noexcept {
  if (k >= boxes_.size() || boxes_[k].mover < 0) return;
  Box& b = boxes_[k];
  Mover& m = movers_[std::size_t(b.mover)];
  clamp_centre(pose.center, m.rest, m.motion, b.cx, b.cy, b.cz);
  // Unit axes, so that the box stays inside the bounds of everywhere it may go.
  for (int a = 0; a < 3; ++a) {
    const std::array<float, 3>& e = pose.axes[std::size_t(a)];
    const double norm = std::sqrt(double(e[0]) * e[0] + double(e[1]) * e[1] + double(e[2]) * e[2]);
    for (int c = 0; c < 3; ++c) b.axes[a][c] = norm > 0.0 && std::isfinite(norm) ? double(e[std::size_t(c)]) / norm : double(a == c);
  }
  const double centre[3] = {b.cx, b.cy, b.cz};
  double reach[3];
  for (int c = 0; c < 3; ++c) reach[c] = std::abs(b.axes[0][c]) * b.hx + std::abs(b.axes[1][c]) * b.hy + std::abs(b.axes[2][c]) * b.hz;
  set_bounds(m.lo, m.hi, centre, reach);
}

void SceneObjects::move_sphere(std::size_t k, const std::array<float, 3>& center) noexcept {
  if (k >= spheres_.size() || spheres_[k].mover < 0) return;
  Sphere& sp = spheres_[k];
  Mover& m = movers_[std::size_t(sp.mover)];
  clamp_centre(center, m.rest, m.motion, sp.cx, sp.cy, sp.cz);
  const double centre[3] = {sp.cx, sp.cy, sp.cz}, reach[3] = {sp.radius, sp.radius, sp.radius};
  set_bounds(m.lo, m.hi, centre, reach);
}

bool SceneObjects::occluded(const SceneRay& r, double t_min, double t_max, bool floor) const noexcept {
  // The objects are cheap next to the floor walk: test them first.
  if (hit_objects(r, t_min, t_max, true).kind != HitKind::none) return true;
  return floor && floor_hit(r, t_min, t_max, nullptr, true) < t_max;
}

LinearRgb SceneObjects::albedo(const SurfaceHit& hit) const noexcept {
  switch (hit.kind) {
    case HitKind::box:
      return boxes_[hit.index].colour;
    case HitKind::sphere:
      return spheres_[hit.index].colour;
    case HitKind::floor:
      return sand_;
    case HitKind::none:
      break;
  }
  return {};
}

}  // namespace houle::detail
