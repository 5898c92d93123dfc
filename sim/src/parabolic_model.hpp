// The parabolic mild-slope model of one train (docs/physics.md 10): the complex amplitude of the
// train's frequency marched row by row along its direction of travel over the scene's floor, so that
// refraction, shoaling and diffraction come out together, once per scene. The sea surface reads the
// result in place of the rays' incident field and the pierheads' diffracted waves (sea_surface.hpp).
// Internal to houle_sim.
#pragma once
#include <complex>
#include <cstdint>
#include <optional>
#include <vector>

#include "houle/runtime/expected.hpp"
#include "houle/sim/bathymetry.hpp"
#include "houle/sim/scene.hpp"

namespace houle::detail {

/// The train as the model starts it, upstream of the domain: straight crests of wavenumber k_far
/// (rad/m) along (dir_x, dir_y), phase k_far (dir . p) - far_offset, deep-water amplitude A0 shoaled
/// to the local depth (the tracer's and the sea surface's convention for the far field).
struct ParabolicTrain {
  double omega = 0.0;         ///< rad/s
  double dir_x = 1.0, dir_y = 0.0;
  double amplitude0 = 0.0;    ///< m
  double k_far = 0.0;         ///< rad/m
  double far_offset = 0.0;    ///< rad
  double dry_depth = 0.0;     ///< m: shallower water (and land) carries no wave (dwt's h_min)
};

/// The field on the march grid: row r lies across the train at s_r (s = dir . p, increasing), column
/// j at n = n0 + j dn (n = dir turned left . p). Between rows the field is demodulated by the
/// reference phase Phi, linear in s, so that it varies slowly and interpolates bilinearly.
struct ParabolicField {
  double dir_x = 1.0, dir_y = 0.0;
  double n0 = 0.0, dn = 1.0;  ///< m
  std::uint32_t columns = 0;
  std::vector<double> s;      ///< per row, m
  std::vector<double> phase;  ///< per row, Phi(s_r), rad
  std::vector<std::complex<float>> eta;  ///< rows x columns: the surface's complex amplitude e^{-i Phi} (m)
  double resolved_wavelength = 0.0;  ///< m, the shortest wavelength given points_per_wavelength columns
  std::uint64_t broken = 0;   ///< nodes where the wave was breaking (Dally, Dean & Dalrymple 1985)
  std::uint64_t wall_tests = 0;  ///< a row's look at a wall segment, or one of a node's three tests against it

  std::size_t rows() const noexcept { return s.size(); }
  /// The complex amplitude at (x, y) times e^{-i reference} (the field relative to a phase there):
  /// its magnitude and phase interpolated bilinearly over the four nodes around (x, y) (a plane wave's
  /// phase turns by up to a radian between nodes, where a bilinear mix of the complex values would dip
  /// in magnitude and ripple in phase gradient), leaving out the nodes with no wave (on land, in a
  /// wall, or just past one: exactly 0) and those for which `across(node_x, node_y)` is true (a wall
  /// between the node and the point); none off the grid or where no node is left.
  template <class Across>
  std::optional<std::complex<double>> relative(double x, double y, double reference, Across&& across) const noexcept {
    if (s.size() < 2 || columns < 2) return std::nullopt;
    const double sp = dir_x * x + dir_y * y, np = -dir_y * x + dir_x * y;
    const double u = (np - n0) / dn;
    if (!(sp >= s.front() && sp <= s.back() && u >= 0.0 && u <= double(columns - 1))) return std::nullopt;
    const std::size_t r = row_before(sp), j = std::min(std::size_t(u), std::size_t(columns) - 2);
    const double fs = (sp - s[r]) / (s[r + 1] - s[r]), fn = u - double(j);
    std::complex<double> v[4];
    double w[4], weight = 0.0;
    std::size_t anchor = 4;
    for (std::size_t c = 0; c < 4; ++c) {
      const std::size_t row = r + c / 2, col = j + c % 2;
      v[c] = std::complex<double>(eta[row * columns + col]);
      w[c] = (c / 2 ? fs : 1.0 - fs) * (c % 2 ? fn : 1.0 - fn);
      const double cn = n0 + double(col) * dn;
      if (w[c] <= 0.0 || v[c] == 0.0 || across(s[row] * dir_x - cn * dir_y, s[row] * dir_y + cn * dir_x)) w[c] = 0.0;
      weight += w[c];
      if (w[c] > 0.0 && (anchor == 4 || w[c] * std::abs(v[c]) > w[anchor] * std::abs(v[anchor]))) anchor = c;
    }
    if (!(weight > 0.0)) return std::nullopt;
    // Phases relative to the heaviest node's, each within half a turn of it.
    double magnitude = 0.0, turn = 0.0;
    for (std::size_t c = 0; c < 4; ++c) {
      if (w[c] <= 0.0) continue;
      magnitude += w[c] * std::abs(v[c]);
      turn += w[c] * std::arg(v[c] * std::conj(v[anchor]));
    }
    return std::polar(magnitude / weight, std::arg(v[anchor]) + turn / weight + reference_turn(r, fs, reference));
  }

 private:
  std::size_t row_before(double sp) const noexcept;
  double reference_turn(std::size_t r, double fs, double reference) const noexcept;
};

/// The depth where a train's far field holds: where it comes into the domain, at the centre of the
/// domain's upstream side (the sea surface's far field and the march start from it).
double entry_depth(const Scene& scene, const Bathymetry& floor, double dir_x, double dir_y) noexcept;

/// Train `train` of a valid scene as the march starts it; far_offset 0 (the sea surface sets its far
/// field's).
ParabolicTrain parabolic_train(const Scene& scene, const Bathymetry& floor, std::size_t train) noexcept;

/// Nodes of the march grid of a train (its memory: 8 bytes a node); never above max_parabolic_nodes.
inline constexpr std::uint64_t max_parabolic_nodes = 1ull << 22;
std::uint64_t parabolic_nodes(const Scene& scene, const Bathymetry& floor, const ParabolicTrain& train);

/// What the march of a train is expected to do, for the build's estimate: the nodes it takes (at most
/// parabolic_nodes: its step follows the rows' mean wavenumber, estimated from the depths on a coarse
/// lattice), and a bound on its wall tests (the wet, reached and open tests of the nodes near each wall
/// segment, and each row's look at the segments).
struct ParabolicWork {
  std::uint64_t nodes = 0, wall_tests = 0;
};
ParabolicWork parabolic_work(const Scene& scene, const Bathymetry& floor, const ParabolicTrain& train);

/// Marches one train over a valid scene's floor, walls and land.
Expected<ParabolicField> march_parabolic(const Scene& scene, const Bathymetry& floor, const ParabolicTrain& train);

}  // namespace houle::detail
