#include "houle/sim/diffraction.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "fresnel_integrals.hpp"

namespace houle {
namespace {

using cplx = std::complex<double>;
constexpr double pi = std::numbers::pi;
constexpr double two_pi = 2.0 * std::numbers::pi;
// Slack for angles a caller built as sums (beta + gamma + pi/2 lands an ulp past 2 pi on the lee face).
constexpr double angle_slack = 1e-12;

// One Sommerfeld term G(s) e^{-i kr cos psi}, s = sqrt(2kr) cos(psi/2). With v = s sqrt(2/pi) and
// aux = g(|v|) + i f(|v|) (fresnel_integrals.hpp), G(s) = ((1-i)/2) int_{-v}^inf e^{i pi t^2/2} dt, and
// the Fresnel phase pi v^2/2 = kr (1 + cos psi) combines with the plane-wave phase into exactly kr:
//   v <  0 (this term's shadow):  ((1-i)/2) aux(|v|) e^{ikr}                  the diffracted wave alone
//   v >= 0 (lit):                 e^{-ikr cos psi} - ((1-i)/2) aux(v) e^{ikr}   plane wave minus it
// So the shadow value comes from the small tail itself, never from 1 - (...), and no large phase
// is formed only to be cancelled. Both branches give e^{ikr}/2 at v = 0.
cplx sommerfeld_term(double sqrt_4kr_over_pi, double k_r, double psi, cplx radial) noexcept {
  const double v = sqrt_4kr_over_pi * std::cos(0.5 * psi);
  const cplx diffracted = cplx{0.5, -0.5} * detail::fresnel_aux(v) * radial;
  if (v < 0.0) return diffracted;
  return std::polar(1.0, -k_r * std::cos(psi)) - diffracted;
}

std::complex<float> sommerfeld_term_fg(double sqrt_4kr_over_pi, double k_r, double psi,
                                       std::complex<float> radial) noexcept {
  const double v = sqrt_4kr_over_pi * std::cos(0.5 * psi);
  const std::complex<float> diffracted = std::complex<float>{0.5f, -0.5f} * detail::fresnel_aux_fg(float(v)) * radial;
  if (v < 0.0) return diffracted;
  return std::polar(1.0f, float(std::remainder(-k_r * std::cos(psi), two_pi))) - diffracted;
}

// [GL98] eqs. 3-4, the Larras fit of the normalised Fresnel modulus (pi/2 convention). The paper
// gives eq. 4 no range; it is the branch for U < 0.75 (0.5 at U = 0, -> 0.03 in the deep shadow),
// and the two meet at 0.75 only to within 0.0044, a jump we keep: this is the paper's model.
double larras_fit(double U) noexcept {
  if (U >= 0.75) return 1.0 + 0.014 * std::exp(-0.4 * U + 3.0) * std::sin(32.0 * std::log1p(U / 15.0) * (U - 0.75));
  return 0.03 + 0.47 * std::exp(0.96 * U);
}

// [GL98] eqs. 1, 3-5 in the paper's variables. `corrected` applies docs/physics.md 4.3 items 2 and 4:
// U in the pi/2 convention the fit was made for (x sqrt(2/pi)), and Phi the plane-wave phase
// difference 2 kr sin(theta0) sin(theta) between incident and reflected waves, with no "+ gamma".
double paper_K(bool corrected, double r_over_L, double beta, double gamma, double alpha) noexcept {
  double a = 2.0 * std::sqrt(pi * r_over_L);
  if (corrected) a *= std::sqrt(2.0 / pi);
  const double Hi = larras_fit(a * std::sin(pi / 4 - beta / 2.0));
  const double Hr = larras_fit(a * std::sin(pi / 4 - beta / 2.0 - gamma));
  const double Phi = corrected ? 4.0 * pi * r_over_L * std::sin(gamma) * std::cos(beta + gamma)
                               : 4.0 * pi * r_over_L * std::sin(gamma) * std::cos(beta) + gamma;
  // The sum of squares can round below 0 where Hi = alpha Hr and cos Phi = -1.
  return std::sqrt(std::max(0.0, Hi * Hi + alpha * alpha * Hr * Hr + 2.0 * alpha * Hi * Hr * std::cos(Phi)));
}

// Ray phase of a [GL98] tracer: incident plane wave -kr cos(theta - theta0) = kr sin(beta) up to the
// shadow line, diffracted rays from M (kr) behind it; equal at beta = pi/2.
double paper_phase(double r_over_L, double beta) noexcept {
  const double k_r = two_pi * r_over_L;
  return std::remainder(beta <= pi / 2 ? k_r * std::sin(beta) : k_r, two_pi);
}

DiffractionSample exact_sample(double r_over_L, double theta, double theta0, double alpha) noexcept {
  const cplx F = sommerfeld_field(two_pi * r_over_L, theta, theta0, alpha);
  const double K = std::abs(F);
  return {K, K > 0.0 ? std::arg(F) : 0.0};
}

// Takes x within angle_slack outside [lo, hi] onto the end; false if x is still outside (or NaN).
bool snap_into(double& x, double lo, double hi) noexcept {
  if (x < lo && x >= lo - angle_slack) x = lo;
  if (x > hi && x <= hi + angle_slack) x = hi;
  return x >= lo && x <= hi;
}

Expected<void> check_common(DiffractionModel model, double r_over_L, double alpha) {
  if (model != DiffractionModel::exact && model != DiffractionModel::paper &&
      model != DiffractionModel::paper_corrected) {
    return Error{"model", "exact, paper or paper_corrected"};
  }
  if (!(r_over_L >= 0.0) || !std::isfinite(r_over_L)) {
    return Error{"r_over_L", "a finite value >= 0, got " + std::to_string(r_over_L)};
  }
  if (!(alpha >= 0.0 && alpha <= 1.0))
    return Error{"alpha", "a reflection coefficient in [0, 1], got " + std::to_string(alpha)};
  return {};
}

}  // namespace

std::string_view diffraction_model_name(DiffractionModel model) noexcept {
  switch (model) {
    case DiffractionModel::exact:
      return "exact";
    case DiffractionModel::paper:
      return "paper";
    case DiffractionModel::paper_corrected:
      return "paper_corrected";
  }
  return "unknown";
}

std::optional<DiffractionModel> parse_diffraction_model(std::string_view name) noexcept {
  if (name == "exact") return DiffractionModel::exact;
  if (name == "paper") return DiffractionModel::paper;
  if (name == "paper_corrected" || name == "paper-corrected") return DiffractionModel::paper_corrected;
  return std::nullopt;
}

Expected<BreakwaterFrame> make_breakwater_frame(const Breakwater& breakwater, double wave_dir_x, double wave_dir_y,
                                                double wavelength) {
  if (!std::isfinite(breakwater.tip_x) || !std::isfinite(breakwater.tip_y))
    return Error{"breakwater.tip", "a finite point (m)"};
  const double n = std::hypot(breakwater.dir_x, breakwater.dir_y);
  if (!(n > 0.0) || !std::isfinite(n)) return Error{"breakwater.dir", "a finite non-zero vector"};
  const double w = std::hypot(wave_dir_x, wave_dir_y);
  if (!(w > 0.0) || !std::isfinite(w)) return Error{"wave_dir", "a finite non-zero vector"};
  if (!(wavelength > 0.0) || !std::isfinite(wavelength)) return Error{"wavelength", "a finite value > 0 m"};

  BreakwaterFrame f;
  f.tip_x = breakwater.tip_x;
  f.tip_y = breakwater.tip_y;
  f.ux = breakwater.dir_x / n;
  f.uy = breakwater.dir_y / n;
  // Where the waves come from (-wave_dir) in the frame (u, counter-clockwise normal).
  const double c = -(wave_dir_x * f.ux + wave_dir_y * f.uy) / w;
  const double s = -(wave_dir_y * f.ux - wave_dir_x * f.uy) / w;
  // Waves from the clockwise side: flip the normal, so the exposed side is always theta in (0, pi).
  f.mirrored = s < 0.0;
  f.vx = f.mirrored ? f.uy : -f.uy;
  f.vy = f.mirrored ? -f.ux : f.ux;
  f.theta0 = std::atan2(std::fabs(s), c);  // fabs: s = -0 must not give -pi
  f.inv_wavelength = 1.0 / wavelength;
  return f;
}

BreakwaterPolar breakwater_polar(const BreakwaterFrame& frame, double x, double y) noexcept {
  const double dx = x - frame.tip_x, dy = y - frame.tip_y;
  const double u = dx * frame.ux + dy * frame.uy;
  const double v = dx * frame.vx + dy * frame.vy;
  BreakwaterPolar p;
  p.r = std::hypot(dx, dy);
  p.r_over_L = p.r * frame.inv_wavelength;
  if (p.r == 0.0) {
    p.theta = pi;
    p.kind = BreakwaterPointKind::pierhead;
  } else if (v == 0.0 && u > 0.0) {
    p.theta = 0.0;
    p.kind = BreakwaterPointKind::on_structure;
  } else {
    // v + 0.0 turns -0 into +0, so the line behind the tip (v = 0, u < 0) is pi, never -pi.
    p.theta = std::atan2(v + 0.0, u);
    if (p.theta < 0.0) p.theta += two_pi;  // the cut moves onto the structure
  }
  p.theta0 = frame.theta0;
  p.gamma = frame.theta0;
  p.beta = p.theta - p.gamma - pi / 2;
  return p;
}

std::complex<double> sommerfeld_field(double k_r, double theta, double theta0, double alpha) noexcept {
  const double s = std::sqrt(4.0 / pi * k_r);
  const cplx radial = std::polar(1.0, k_r);
  return sommerfeld_term(s, k_r, theta - theta0, radial) + alpha * sommerfeld_term(s, k_r, theta + theta0, radial);
}

std::complex<double> sommerfeld_reflected(double k_r, double theta, double theta0) noexcept {
  return sommerfeld_term(std::sqrt(4.0 / pi * k_r), k_r, theta + theta0, std::polar(1.0, k_r));
}

std::complex<float> sommerfeld_field_fg(double k_r, double theta, double theta0, float alpha) noexcept {
  const double s = std::sqrt(4.0 / pi * k_r);
  const std::complex<float> radial = std::polar(1.0f, float(std::remainder(k_r, two_pi)));
  return sommerfeld_term_fg(s, k_r, theta - theta0, radial) +
         alpha * sommerfeld_term_fg(s, k_r, theta + theta0, radial);
}

Expected<DiffractionSample> diffraction(DiffractionModel model, double r_over_L, double theta, double theta0,
                                        double alpha) {
  if (Expected<void> common = check_common(model, r_over_L, alpha); !common) return common.error();
  if (!(theta0 >= 0.0 && theta0 <= pi)) return Error{"theta0", "in [0, pi] rad, got " + std::to_string(theta0)};
  if (!snap_into(theta, 0.0, two_pi))
    return Error{"theta", "in [0, 2 pi] rad (the water), got " + std::to_string(theta)};
  if (model == DiffractionModel::exact) return exact_sample(r_over_L, theta, theta0, alpha);
  const double beta = theta - theta0 - pi / 2;
  return DiffractionSample{paper_K(model == DiffractionModel::paper_corrected, r_over_L, beta, theta0, alpha),
                           paper_phase(r_over_L, beta)};
}

Expected<DiffractionSample> diffraction_at_beta(DiffractionModel model, double r_over_L, double beta, double gamma,
                                                double alpha) {
  if (Expected<void> common = check_common(model, r_over_L, alpha); !common) return common.error();
  if (!(gamma >= 0.0 && gamma <= pi)) return Error{"gamma", "in [0, pi] rad, got " + std::to_string(gamma)};
  if (!snap_into(beta, -pi / 2 - gamma, 1.5 * pi - gamma)) {
    return Error{"beta",
                 "in [-pi/2 - gamma, 3 pi/2 - gamma] rad (the water between the faces), got " + std::to_string(beta)};
  }
  if (model == DiffractionModel::exact) {
    return exact_sample(r_over_L, std::clamp(beta + gamma + pi / 2, 0.0, two_pi), gamma, alpha);
  }
  return DiffractionSample{paper_K(model == DiffractionModel::paper_corrected, r_over_L, beta, gamma, alpha),
                           paper_phase(r_over_L, beta)};
}

}  // namespace houle
