// Diffraction of a monochromatic plane wave by a thin semi-infinite breakwater (docs/physics.md 4).
//
// Local frame (docs/physics.md 4.2). The pierhead M is the origin and the structure is the half-line
// theta = 0 = 2 pi. A point P is (r, theta), r >= 0 in m, theta in [0, 2 pi] rad counter-clockwise
// from the structure: theta = 0 is the exposed face, theta = 2 pi the lee face, theta = pi the line
// straight behind the tip. The waves COME FROM direction theta0 in [0, pi] (they propagate along
// -(cos theta0, sin theta0)); theta0 = pi/2 is normal incidence. The branch cut of theta lies on the
// structure, where there is no water, so every function here is continuous across the water
// (theta = pi included). Paper notation [GL98]: gamma = theta0, beta = theta - gamma - pi/2
// (beta = pi/2 is the shadow line, beta > pi/2 the shadow; water is beta in
// [-pi/2 - gamma, 3 pi/2 - gamma], the ends being the two faces).
//
// Field (time factor e^{-i omega t}, unit incident amplitude, phase 0 at M):
//   F = G(s1) e^{-i k r cos(theta - theta0)} + alpha G(s2) e^{-i k r cos(theta + theta0)},
//   s1,2 = sqrt(2 k r) cos((theta -+ theta0)/2),  G(s) = e^{-i pi/4}/sqrt(pi) int_{-inf}^{s} e^{i t^2} dt.
// alpha = 1 is the exact Sommerfeld / Penney & Price (1952) solution for a rigid, fully reflecting
// barrier; alpha = 0 keeps the incident term only (the usual Kirchhoff-type approximation for an
// absorbing barrier, not an exact solution); alpha in between is a heuristic for partial reflection
// (docs/physics.md 4.4). The surface elevation is A_M |F| cos(arg F - omega t).
#pragma once
#include <complex>
#include <cstdint>
#include <optional>
#include <string_view>

#include "houle/runtime/expected.hpp"

namespace houle {

/// `exact`: |F| and arg F above. `paper`: [GL98] eqs. 1, 3, 4, 5 exactly as printed (the Larras fit;
/// eq. 4 taken for U < 0.75). `paper_corrected`: the same with the two typos of docs/physics.md 4.3
/// fixed (U scaled by sqrt(2/pi); Phi = 4 pi (r/L) sin(gamma) cos(beta + gamma)). The paper models
/// are kept for comparison only: against `exact` (alpha = 1, r/L in [0.5, 10], every beta) they err
/// by up to 2.17 (paper) and 0.38 (paper_corrected) in K, 0.23 and 0.06 on average.
enum class DiffractionModel : std::uint8_t { exact, paper, paper_corrected };

/// "exact", "paper", "paper_corrected".
std::string_view diffraction_model_name(DiffractionModel model) noexcept;
/// Inverse of diffraction_model_name; also accepts "paper-corrected".
std::optional<DiffractionModel> parse_diffraction_model(std::string_view name) noexcept;

/// A semi-infinite breakwater in world coordinates (m).
struct Breakwater {
  double tip_x = 0.0, tip_y = 0.0;  ///< pierhead M, m
  double dir_x = 1.0, dir_y = 0.0;  ///< from M along the structure (normalised on use)
};

/// A breakwater and an incident wave train reduced to the local frame, once per scene.
struct BreakwaterFrame {
  double tip_x = 0.0, tip_y = 0.0;  ///< M, m
  double ux = 1.0, uy = 0.0;        ///< unit vector from M along the structure (theta = 0)
  double vx = 0.0, vy = 1.0;        ///< unit normal towards the exposed side (theta = pi/2)
  double theta0 = 0.0;              ///< rad in [0, pi]: where the waves come from, local frame
  double inv_wavelength = 0.0;      ///< 1/L, 1/m
  /// True when the waves come from the clockwise side of `dir`: the local frame is then mirrored
  /// (v is the clockwise normal) so that 0 <= theta0 <= pi still holds. theta0 = 0 exactly (waves
  /// running along the structure towards its tip) counts as not mirrored.
  bool mirrored = false;
};

/// Fails (field "breakwater.tip", "breakwater.dir", "wave_dir", "wavelength") on non-finite
/// input, a zero direction or a wavelength that is not > 0 m.
Expected<BreakwaterFrame> make_breakwater_frame(const Breakwater& breakwater, double wave_dir_x, double wave_dir_y,
                                                double wavelength);

enum class BreakwaterPointKind : std::uint8_t {
  water,         ///< an ordinary point, theta in (0, 2 pi) or a face approached from the water
  on_structure,  ///< exactly on the structure's line (v = 0, u > 0): reported as theta = 0
  pierhead,      ///< r = 0: reported as theta = pi (every model's value is independent of theta there)
};

/// Polar coordinates of a point about the pierhead, in both notations.
struct BreakwaterPolar {
  double r = 0.0;         ///< m
  double r_over_L = 0.0;  ///< r / wavelength
  double theta = 0.0;     ///< rad in [0, 2 pi]
  double theta0 = 0.0;    ///< rad in [0, pi] (the frame's)
  double beta = 0.0;      ///< rad, theta - gamma - pi/2
  double gamma = 0.0;     ///< rad, = theta0
  BreakwaterPointKind kind = BreakwaterPointKind::water;
};

/// Local polar coordinates of world point (x, y) m. theta = atan2(v, u) taken into [0, 2 pi], so the
/// only discontinuity is on the structure. A point exactly on the structure's line (both signs of
/// zero) has no side: it is reported deterministically as the exposed face, theta = 0, with kind
/// on_structure; a caller that knows it came from the lee side may use theta = 2 pi instead.
/// Points a rounding error off the line get theta ~ 0 or ~ 2 pi by the sign of v, each the right
/// face's limit. Non-finite (x, y) give NaN coordinates.
BreakwaterPolar breakwater_polar(const BreakwaterFrame& frame, double x, double y) noexcept;

/// F above at k r = k_r >= 0 (rad), theta in [0, 2 pi], theta0 in [0, pi], alpha in [0, 1]; inputs
/// are not checked (outside these ranges the result is not a physical field: use diffraction()).
/// Written so that nothing cancels: in the shadow of a term (s < 0) it is computed from the small
/// Fresnel tail, and the Fresnel phase is merged analytically with the plane-wave phase into k r.
/// Finite everywhere, including k_r = 0 (F = (1 + alpha)/2) and theta0 = 0 (then F = 2 G(s1)
/// e^{-i k r cos theta} for alpha = 1). Agrees with scipy-based evaluation to 2e-15 for r < 10 L and
/// 3e-14 up to 300 L: the plane-wave phase k r cos(.) carries an unavoidable error of ~k r 1e-16 rad.
std::complex<double> sommerfeld_field(double k_r, double theta, double theta0, double alpha) noexcept;
/// Its part proportional to alpha (sommerfeld_field is linear in alpha): the reflected wave with its
/// diffraction, for a model that carries the incident wave by other means (the parabolic model).
std::complex<double> sommerfeld_reflected(double k_r, double theta, double theta0) noexcept;

/// The same with the Fresnel auxiliary functions from the A&S 7.3.32-33 rational fits and the
/// complex arithmetic in float; angles and phases are formed and reduced modulo 2 pi in double
/// first. |error| <= 2e-3 in F (a reference for float kernels).
std::complex<float> sommerfeld_field_fg(double k_r, double theta, double theta0, float alpha) noexcept;

/// One diffraction sample.
struct DiffractionSample {
  /// Diffraction coefficient K' (docs/physics.md 4; H in [GL98]): local amplitude / incident amplitude.
  double K = 0.0;
  /// rad in [-pi, pi], relative to the incident wave's phase at M.
  /// exact: arg F (0 where F = 0).
  /// paper models (which give no phase): the phase a ray tracer following [GL98] carries, i.e. the
  /// incident plane wave's -k r cos(theta - theta0) on the lit side of the shadow line and the
  /// diffracted rays' k r (circular crests about M) behind it; the two agree on the shadow line.
  /// The reflected wave does not enter it.
  double phase = 0.0;
};

/// The sample at r/L >= 0, theta in [0, 2 pi], theta0 in [0, pi], alpha in [0, 1] (reflection
/// coefficient of the structure; 1 = rigid). Values outside these ranges, or not finite, are
/// rejected with an Error naming the argument ("r_over_L", "theta", "theta0", "alpha"); theta within
/// 1e-12 rad outside [0, 2 pi] is taken as the face (absorbs rounding in callers' angle sums).
Expected<DiffractionSample> diffraction(DiffractionModel model, double r_over_L, double theta, double theta0,
                                        double alpha);

/// The same in the paper's notation: beta must lie in [-pi/2 - gamma, 3 pi/2 - gamma] (1e-12 rad
/// slack as above), gamma in [0, pi]; otherwise an Error on "beta" or "gamma". The paper models use
/// beta and gamma directly, exactly as eqs. 1 and 5 are printed.
Expected<DiffractionSample> diffraction_at_beta(DiffractionModel model, double r_over_L, double beta, double gamma,
                                                double alpha);

}  // namespace houle
