// The build's cost before the build (build_cost.hpp). Memory counts what the code allocates, per
// traced sample, per sea grid node, per floor cell and per pixel (each figure below names its arrays);
// the CPU times are those counts times costs measured on the development machine
// (tests/robust/build_cost_sweep.sh checks both against measured builds).
#include "houle/sim/build_cost.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "houle/sim/animation.hpp"
#include "houle/sim/bathymetry.hpp"
#include "houle/sim/dispersion.hpp"
#include "houle/sim/scene_keys.hpp"
#include "houle/sim/wave_rays.hpp"
#include "clip_line.hpp"
#include "parabolic_model.hpp"
#include "ray_step.hpp"
#include "ray_walls.hpp"
#include "train_tracer.hpp"

namespace houle {
namespace {

constexpr double two_pi = 2.0 * std::numbers::pi;

// Bytes. A traced sample: gathered, x y theta k amplitude phase time (doubles) and flags; staged
// while its train is traced, StagedSample (7 doubles and flags, padded to 64). A reflected wave's
// sample holds more while it is traced, and what its tracer leaves stays resident (measured: Plate 3
// with and without reflection, 25 MiB for 154,000 reflected samples; the coast, 14 MiB for 87,000).
constexpr double sample_kept = 57.0, sample_staged = 64.0, reflected_sample_traced = 120.0;
// An initial ray: its entry on the front, its state in the sweep, its arrays in the output (measured:
// 1.9 million rays entering dry land, 86 MiB); while its train is traced, a ray that takes samples
// also holds its last chunk of 32 staged samples, half full on average, and its sweep state.
constexpr double ray_bytes = 46.0, ray_staged = 1300.0;
// A sea grid node, kept per traced train: phi, b_re, b_im, kx, ky, fold, lean (floats), and K' where a
// pierhead diffracts (the probe's three parts, 12 more, are within the renderer's share it does not build).
constexpr double node_kept = 28.0, node_diffraction = 4.0;
// A node of one train's resampling scratch: the incident family (weight, phase, re, im, kx, ky in
// doubles) and one per reflected wave, wavenumber and kh, the sums (complex double), the carrier
// (phase, kx, ky, reference in doubles), magnitude, the shoreline queue, flags, the march's heap.
constexpr double node_family = 48.0, node_scratch = 8.0 + 16.0 + 32.0 + 8.0 + 4.0 + 4.0 + 8.0;
// Shared by the trains: the depth under each node (float).
constexpr double node_depth = 4.0;
// A floor cell of the renderer's grid: the heights (float) in the render scene and in the renderer.
constexpr double floor_cell_bytes = 8.0;
// An object (a wall's block, a box, a sphere): in the render scene, the renderer's list and its hierarchy.
constexpr double object_bytes = 160.0;
// Per pixel: the renderer's row scratch and the caller's frame (linear RGB floats and an encoded copy).
constexpr double pixel_bytes = 64.0;
// The program: code, libraries, the sky and water tables, the threads' stacks.
constexpr double program_bytes = 10.0 * 1048576.0;
// Samples of inserted rays, for each sample of the initial rays where the floor refracts (the coast
// and Plate 3: 1.9 and 2.0), and of a reflected wave for each of its train's (0.4 and 0.75; 32
// jetties across a beach, 0.2).
constexpr double inserted_per_initial = 1.0, reflected_per_incident = 0.5;

// CPU seconds (one core of the development machine).
constexpr double per_sample_s = 0.7e-6;         // a traced sample: the step, tubes, insertion, the gather
constexpr double per_ray_s = 2.5e-6;            // an initial ray: its entry, state and gather; three
                                                // times that where walls reflect (1.9 million rays
                                                // entering land: 2.8 us each; 5 million beside 11
                                                // reflecting walls: 8.9 us)
constexpr double per_splat_s = 8.0e-9;          // a sample spread onto one grid node
constexpr double per_node_s = 0.9e-6;           // a sea node of one traced train: the passes and the march
constexpr double per_parabolic_node_s = 0.25e-6;  // the same on the parabolic model, which reads it from
                                                  // its march (a 2 km height map, 4 million nodes at
                                                  // draft: under 1 s on the Zen 3 machine)
constexpr double per_march_node_s = 1.5e-6;     // a node of the parabolic model's march (the elliptic shoal:
                                                // 52,000 nodes in 80 ms), as many as its rows expected
                                                // from the depths (a 400 m beach with a shoal and 1.5 s
                                                // waves: 2.5 million, the whole build 1.9 s on the
                                                // Zen 4 machine). Counting the rows' bound instead, at
                                                // the shortest wavelength, a 2 km height map was
                                                // estimated at 4 times its build. The fuzzers' time
                                                // limits rely on the estimate bounding the build from
                                                // above.
constexpr double march_node_bytes = 8.0;        // its complex float (parabolic_model.hpp)
constexpr double per_diffraction_s = 0.12e-6;   // a pierhead's diffracted wave at one node
constexpr double per_radial_s = 60.0e-9;        // a pierhead's radial table entry (non-uniform floor)
constexpr double per_depth_s = 60.0e-9;         // a floor sample, base and height map
constexpr double per_block_s = 3.0e-6;          // a wall's block or an object: placed, bounded, in the
                                                // hierarchy, its pages first touched (232 walls of
                                                // 100 km segments, 9 million blocks: 30 s)
constexpr double per_feature_s = 12.0e-9;       // one shoal, bar or channel visited by a floor sample
                                                // (1,024 of each on a 200 m beach: 25 ns on the Zen 3
                                                // machine, where 4 ns left its trace 5 times over)
constexpr double per_wall_test_s = 5.0e-9;      // a chord tested against one wall: each traced step, each
                                                // carrier move (16 a node) near a wall

// Bytes as a count: an estimate past 2^58 (or not a number) is as refused as any over the limit.
std::uint64_t count(double v) { return v >= 0.0 && v < 0x1p58 ? std::uint64_t(v) : std::uint64_t(1) << 58; }

std::uint64_t grid_nodes(const Domain& d, double cell) {
  return std::uint64_t(std::ceil((d.x_max - d.x_min) / cell) + 1.0) * std::uint64_t(std::ceil((d.y_max - d.y_min) / cell) + 1.0);
}

// Samples train t is expected to take: its initial rays, each marched straight at the tracer's
// phase step (shorter steps where the water shoals) until it leaves the domain, meets a wall or
// the water is too shallow, estimated from up to 16 rays across the front, within the caps; and the
// floor samples each of them costs: the tracer's RK4 takes three a sub-step and one more a step, in
// as many sub-steps as the floor's length scale and the ray's turn rate ask for (ray_step.hpp),
// which a rough floor multiplies (1,024 each of shoals, bars and channels: 15 a sample). Also how
// often a probe's turn rate changes sign, a feature focusing then spreading the rays: each such
// feature splits the tubes round it and insertion about doubles the rays (ray_growth).
struct TrainSamples {
  double samples = 0.0, depths_per_sample = 0.0;
  double turn_reversals = 0.0, steps_per_ray = 0.0;  // per probe
};

TrainSamples expected_samples(const Scene& s, std::size_t t, const Bathymetry& floor,
                              const std::vector<detail::Capsule>& walls, const FrontSize& f) {
  const DwtSettings& set = s.dwt;
  const double omega = train_omega(s.trains[t]);
  const double h_min = std::max(set.min_depth, set.min_depth_wavelengths * two_pi / deep_water_wavenumber(omega));
  const detail::Medium medium = detail::make_medium(s, floor, omega, h_min);
  const Point2 dir = train_direction(s.trains[t]);
  const double theta = std::atan2(dir.y, dir.x);
  const std::size_t probes = std::min<std::size_t>(f.rays, 16);
  struct Probe {
    double x, y, k;
  };
  std::vector<Probe> entries;
  double k_ref = INFINITY;
  for (std::size_t i = 0; i < probes; ++i) {
    const double c = (double(i) + 0.5) * f.width / double(probes);
    const double px = f.start.x - c * dir.y, py = f.start.y + c * dir.x;
    double t0 = 0.0, t1 = 0.0;
    if (!detail::clip_line(s.domain, px, py, dir.x, dir.y, t0, t1)) continue;
    const double x = px + t0 * dir.x, y = py + t0 * dir.y, h = floor.depth(x, y);
    if (!(h > h_min)) {
      entries.push_back({x, y, 0.0});
      continue;
    }
    entries.push_back({x, y, linear_wave(omega, h).k});
    k_ref = std::min(k_ref, entries.back().k);
  }
  if (entries.empty() || !std::isfinite(k_ref)) return {};
  const double dphi = k_ref * set.step, path_max = 4.0 * ((s.domain.x_max - s.domain.x_min) + (s.domain.y_max - s.domain.y_min));
  const double per_ray_cap = double(set.max_samples) / double(f.rays) + 1.0;
  double steps = 0.0, walked = 0.0, depths = 0.0, reversals = 0.0;
  for (const Probe& e : entries) {
    if (e.k == 0.0) continue;
    double x = e.x, y = e.y, path = 0.0, n = 1.0, last_turn = 0.0;
    // At most 4096 steps each, then the rest at the last step's length.
    for (int i = 0; i < 4096 && n < per_ray_cap; ++i, ++n) {
      const detail::LocalWave w = detail::wave_at(medium, x, y);
      if (!(w.depth > h_min)) break;
      const double ds = dphi / w.k, turn_rate = detail::ray_rate(w, theta).theta, turn = std::fabs(turn_rate) * dphi;
      // Turns under 1e-4 rad a step (a plane beach's oblique refraction far out) keep no sign.
      if (turn > 1e-4) {
        if (turn_rate * last_turn < 0.0) reversals += 1.0;
        last_turn = turn_rate;
      }
      depths += 1.0 + 3.0 * std::clamp(std::max(std::ceil(ds / medium.ds_max), std::ceil(turn / medium.max_turn)), 1.0, 256.0);
      walked += 1.0;
      if (!walls.empty() && detail::wall_blocks(walls, x, y, x + ds * dir.x, y + ds * dir.y)) break;
      x += ds * dir.x, y += ds * dir.y, path += ds;
      if (x < s.domain.x_min || x > s.domain.x_max || y < s.domain.y_min || y > s.domain.y_max || path > path_max) break;
      if (i == 4095) {
        double t0 = 0.0, t1 = 0.0;
        double left = detail::clip_line(s.domain, x, y, dir.x, dir.y, t0, t1) ? std::min(t1, path_max - path) : 0.0;
        if (!walls.empty()) left *= std::min(1.0, detail::first_wall_hit(walls, x, y, x + left * dir.x, y + left * dir.y).u);
        n += left / ds;
      }
    }
    steps += std::min(n, per_ray_cap);
  }
  const double probed = double(entries.size());
  return {std::min(double(set.max_samples), steps / probed * double(f.rays)),
          medium.uniform || walked == 0.0 ? 0.0 : depths / walked, reversals / probed, steps / probed};
}

// The samples of a train whose initial rays take `initial` (with the insertion a smooth floor
// causes): each feature the rays cross (two turn reversals) about doubles them, up to dwt.max_rays,
// inserted late on average (a quarter of the way), or, where the parabolic model marches the train,
// up to its budget of marched_ray_factor rays per initial ray, reached early (70 % of the way).
// Measured on random floors of 16 to 1,024 each of shoals, bars and channels, 200 m across: 1.0-2.0
// times the samples traced with rays, 0.9-1.5 times marched; the shipped scenes reverse 0-0.25
// times a probe.
double ray_growth(const TrainSamples& e, double initial, double initial_rays, bool marched, const DwtSettings& set) {
  const double grown = initial * std::exp2(0.5 * e.turn_reversals);
  const double capped = marched ? std::min(double(set.max_rays), double(detail::marched_ray_factor) * initial_rays) *
                                      e.steps_per_ray * 0.7
                                : double(set.max_rays) * e.steps_per_ray / 4.0;
  return std::min(double(set.max_samples), std::max(initial, std::min(grown, capped)));
}

struct TrainTrace {
  double samples = 0.0, depths_per_sample = 0.0;
};

TrainTrace train_trace(const Scene& s, std::size_t t, const Bathymetry& floor, const std::vector<detail::Capsule>& walls) {
  const FrontSize f = front_size(s, t, s.dwt);
  const TrainSamples e = expected_samples(s, t, floor, walls, f);
  const bool marched = scene_wave_model(s).kind == WaveModelKind::parabolic;
  return {ray_growth(e, e.samples * (floor.uniform() ? 1.0 : 1.0 + inserted_per_initial), double(f.rays), marched, s.dwt),
          e.depths_per_sample};
}

}  // namespace

double expected_trace_samples(const Scene& scene, std::size_t train) {
  const Bathymetry floor(scene.floor);
  return train_trace(scene, train, floor, detail::wall_capsules(scene.walls)).samples;
}

BuildCost estimate_build_cost(const Scene& s, const Quality& quality, std::uint64_t pixels, unsigned threads,
                              const WaveField* traced_waves) {
  BuildCost c;
  const Bathymetry floor(s.floor);
  const double cell = quality.sea_cell;
  const double nodes = double(grid_nodes(s.domain, cell));
  const bool reflecting = scene_has_reflecting_walls(s);
  const std::size_t pierheads =
      s.dwt.diffraction ? detail::pierhead_sites(s, floor, s.dwt.min_depth).size() : std::size_t(0);
  const double splat_reach = 2.0 * std::ceil(std::max({s.dwt.step, s.dwt.insertion_distance, 2.0 * cell}) / cell) + 1.0;
  // A radial table per pierhead over a non-uniform floor: 2048 directions to the far corner every 2 cells.
  const double radial = floor.uniform() ? 0.0 : 2048.0 * (std::hypot(s.domain.x_max - s.domain.x_min, s.domain.y_max - s.domain.y_min) / (2.0 * cell) + 2.0);

  const std::vector<detail::Capsule> walls = detail::wall_capsules(s.walls);
  std::size_t traced = 0;
  double samples = 0.0, reflected = 0.0, largest = 0.0, rays = 0.0, depths = 0.0;
  for (std::size_t t = 0; t < s.trains.size(); ++t) {
    if (s.dwt.analytic_shortcut && !train_needs_rays(s, t)) continue;
    ++traced;
    rays += double(front_size(s, t, s.dwt).rays);
    const TrainTrace e = train_trace(s, t, floor, walls);
    const double n = e.samples;
    const double r = reflecting ? std::min(double(s.dwt.max_samples), n * reflected_per_incident) : 0.0;
    samples += n + r;
    depths += (n + r) * e.depths_per_sample;
    reflected += r;
    largest = std::max(largest, n);
  }
  if (traced_waves) {
    // What was traced, and its trace's time spent.
    samples = reflected = largest = rays = 0.0;
    for (const WaveRays& w : traced_waves->trains) {
      samples += double(w.sample_count());
      rays += double(w.ray_count());
      largest = std::max(largest, double(w.sample_count()));
    }
    for (const ReflectedWave& r : traced_waves->reflections) {
      samples += double(r.rays.sample_count());
      reflected += double(r.rays.sample_count());
    }
  }
  c.samples = count(samples);
  const double lanes = std::min<double>(std::max(1u, threads), double(std::max<std::size_t>(traced, 1)));
  const double kept_rays = samples * sample_kept + reflected * reflected_sample_traced + rays * ray_bytes,
               staged = lanes * (largest * sample_staged +
                                 std::min(largest, rays / double(std::max<std::size_t>(traced, 1))) * ray_staged);
  const double wall_count = double(walls.size());
  c.trace_s = samples * (per_sample_s + wall_count * per_wall_test_s) +
              depths * (per_depth_s + floor.features_per_sample() * per_feature_s) +
              rays * (per_ray_s * (reflecting ? 3.0 : 1.0) + wall_count * per_wall_test_s);
  if (traced_waves) c.trace_s = 0.0;
  // Nodes near a wall (within its half thickness and the carrier stencil's reach), where every move is
  // tested against every wall.
  double near_wall = 0.0;
  for (const detail::Capsule& w : walls) {
    const double reach = w.radius + 2.5 * cell;
    near_wall += (std::hypot(w.bx - w.ax, w.by - w.ay) + 2.0 * reach) * 2.0 * reach / (cell * cell);
  }
  near_wall = std::min(near_wall, nodes);
  // The parabolic model's march grids: each lives while its train is resampled (one per lane).
  double march_nodes = 0.0, largest_march = 0.0, march_wall_tests = 0.0;
  const bool parabolic = scene_wave_model(s).kind == WaveModelKind::parabolic;
  if (parabolic) {
    for (std::size_t t = 0; t < s.trains.size(); ++t) {
      if (s.dwt.analytic_shortcut && !train_needs_rays(s, t)) continue;
      const detail::ParabolicTrain train = detail::parabolic_train(s, floor, t);
      const double n = double(detail::parabolic_nodes(s, floor, train));
      const detail::ParabolicWork work = detail::parabolic_work(s, floor, train);
      march_nodes += double(work.nodes);
      march_wall_tests += double(work.wall_tests);
      largest_march = std::max(largest_march, n);
    }
  }
  double kept_sea = 0.0, sea_scratch = 0.0;
  if (traced > 0) {
    kept_sea = nodes * double(traced) * (node_kept + (pierheads > 0 ? node_diffraction : 0.0));
    sea_scratch = nodes * (node_depth + lanes * (node_family * (reflecting ? 2.0 : 1.0) + node_scratch)) +
                  lanes * double(pierheads) * radial * 4.0 + lanes * largest_march * march_node_bytes;
    const double node_s = parabolic ? per_parabolic_node_s : per_node_s;
    c.sea_s = double(traced) * (nodes * (node_s + double(pierheads) * per_diffraction_s) + double(pierheads) * radial * per_radial_s +
                                near_wall * 16.0 * wall_count * per_wall_test_s) +
              samples * splat_reach * splat_reach * per_splat_s +
              nodes * (per_depth_s + floor.features_per_sample() * per_feature_s) + march_nodes * per_march_node_s +
              march_wall_tests * per_wall_test_s;
  }
  const double floor_cells = floor.uniform() && s.floor.base.depth >= 200.0 ? 0.0 : double(grid_nodes(s.domain, 1.0));
  const double map_bytes = s.floor.height_map ? 4.0 * double(s.floor.height_map->depth.size()) : 0.0;
  // The walls' stone blocks, one every 3 m of each segment (render_scene.cpp), and the objects: a box
  // in the render scene, in the renderer and in its hierarchy.
  double blocks = double(s.boxes.size() + s.spheres.size());
  for (const Wall& w : s.walls) {
    for (std::size_t j = 0; j + 1 < w.points.size(); ++j) {
      blocks += std::max(1.0, std::ceil(std::hypot(w.points[j + 1].x - w.points[j].x, w.points[j + 1].y - w.points[j].y) / 3.0));
    }
  }
  const double floor_bytes = floor_cells * floor_cell_bytes + 3.0 * map_bytes + blocks * object_bytes;
  c.floor_s = floor_cells * (per_depth_s + floor.features_per_sample() * per_feature_s) + blocks * per_block_s;
  const double spp = quality.render.samples_per_pixel;
  const double kept_hits = std::min(double(pixels) * spp * double(Renderer::kept_hit_bytes), double(Renderer::max_kept_bytes));
  const double image = double(pixels) * pixel_bytes + kept_hits + double(SurfaceFrame::bytes_bound(quality.surface));
  // The peak is the largest of the build's stages: tracing (the rays kept and the train being
  // gathered), resampling (the rays, the grids kept and a train's scratch per thread), rendering
  // (the rays and grids kept, the floor, the image).
  const double tracing = kept_rays + staged, resampling = kept_rays + kept_sea + sea_scratch,
               rendering = kept_rays + kept_sea + floor_bytes + image;
  c.program = count(program_bytes);
  c.rays = count(kept_rays);
  if (tracing >= resampling && tracing >= rendering) {
    c.rays = count(kept_rays + staged);
  } else if (resampling >= rendering) {
    c.sea = count(kept_sea + sea_scratch);
  } else {
    c.sea = count(kept_sea);
    c.floor = count(floor_bytes);
    c.image = count(image);
  }
  return c;
}

Expected<void> check_build_cost(const BuildCost& c, const std::string& what) {
  const auto mib = [](std::uint64_t b) { return std::to_string((b + (1u << 20) - 1) >> 20) + " MiB"; };
  const std::string parts = "(wave rays " + mib(c.rays) + ", sea grids " + mib(c.sea) + ", floor " + mib(c.floor) +
                            ", image " + mib(c.image) + ")";
  if (!(c.bytes() <= scene_limits::max_animation_bytes)) {
    return Error{"scene", "needs an estimated " + mib(c.bytes()) + " " + what + " " + parts + ", over the limit of " +
                              mib(scene_limits::max_animation_bytes) +
                              ": expected a smaller domain or image, fewer traced trains or pierheads, lower dwt caps "
                              "or a coarser quality"};
  }
  if (!(c.seconds() <= max_build_seconds)) {
    const auto s = [](double v) { return scene_keys::number_text(std::round(v)) + " s"; };
    return Error{"scene", "would take an estimated " + s(c.seconds()) + " of CPU to build " + what + " (tracing " +
                              s(c.trace_s) + ", sea grids " + s(c.sea_s) + ", floor and walls " + s(c.floor_s) +
                              "), over the limit of " + s(max_build_seconds) +
                              ": expected a smaller domain, fewer traced trains or pierheads, a larger dwt.step or "
                              "dwt.insertion_distance, fewer floor features or shorter walls"};
  }
  return {};
}

}  // namespace houle
