// Fresnel integrals (sim/src/fresnel_integrals.hpp) against independent reference values.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <limits>
#include <numbers>

#include "fresnel_integrals.hpp"
#include "angles.hpp"

namespace {

using houle::detail::fresnel;
using houle::detail::fresnel_aux;
using houle::detail::fresnel_aux_fg;
using houle::detail::fresnel_tail;
using houle_test::pi;

// Reference: mpmath 1.2.1 at 50 significant digits (mp.fresnelc, mp.fresnels, pi/2 convention),
// evaluated at the double nearest each x; f and g from (1/2 - C) + i (1/2 - S) = (g + i f) e^{i pi x^2/2}.
// Rounded to 20 digits.
struct Ref {
  double x, c, s, f, g;
};
constexpr Ref refs[] = {
    {0.0, 0.0, 0.0, 0.5, 0.5},
    {1e-08, 1.0000000000000000209e-8, 5.2359877559829890594e-25, 0.49999999999999992146, 0.49999999000000007854},
    {0.1, 0.099997532627085073601, 0.00052358954761221068668, 0.49313182560662363365, 0.40779855452993033363},
    {0.5, 0.49234422587144639288, 0.064732432859999277611, 0.39920505852570223993, 0.17364269961323774796},
    {1.0, 0.77989340037682282947, 0.43825914739035476608, 0.27989340037682282947, 0.061740852609645233923},
    {1.2, 0.71543772292307342426, 0.62340091854624963806, 0.24465632434409281638, 0.042243130977416328368},
    {1.5, 0.44526117603982153506, 0.69750496008209301308, 0.2034184312260139559, 0.025009796942798094223},
    {1.6, 0.36546168344048765296, 0.63888768350938083462, 0.19219389591936834212, 0.021256848886994049882},
    {2.0, 0.4882534060753407545, 0.3434156783636982422, 0.1565843216363017578, 0.0117465939246592455},
    {2.5, 0.45741300964177704525, 0.61918175581959293611, 0.1264069204948635959, 0.0062636346491221377177},
    {3.0, 0.60572078929768562956, 0.4963129989673750361, 0.10572078929768562956, 0.0036870010326249639024},
    {5.0, 0.5636311887040122311, 0.49919138191711688675, 0.063631188704012231102, 0.00080861808288311324807},
    {7.5, 0.51601825015233634634, 0.46070123294683061084, 0.042437245482130788625, 0.00024005360123361468845},
    {10.0, 0.49989869420551572361, 0.4681699785848822404, 0.031830021415117759597, 0.00010130579448427638585},
    {20.0, 0.49998733497234438819, 0.48408453592595389271, 0.015915464074046107285, 0.000012665027655611812994},
    {50.0, 0.49999918943072796796, 0.49363380258593874145, 0.0063661974140612585467, 8.1056927203204418984e-7},
    {100.0, 0.49999989867881789756, 0.49681690114783755327, 0.0031830988521624467285, 1.0132118210244053154e-7},
    {1000.0, 0.49999999989867881636, 0.49968169011381630608, 0.00031830988618369391693, 1.0132118364218378171e-10},
    {100000.0, 0.49999999999999989868, 0.49999681690113816209, 3.1830988618379067154e-6, 1.0132118364233777144e-16},
};

// Relative difference, absolute below |ref| = 1.
double rel_err(double v, double ref) { return std::fabs(v - ref) / std::max(1.0, std::fabs(ref)); }
double rel_only(double v, double ref) { return ref == 0.0 ? std::fabs(v) : std::fabs(v - ref) / std::fabs(ref); }

TEST(FresnelIntegrals, TextbookValues) {
  // Tolerance 1e-12 absolute (the brief's; the implementation reaches ~1e-15).
  constexpr double tol = 1e-12;
  EXPECT_NEAR(fresnel(1.0).c, 0.7798934003768228, tol);
  EXPECT_NEAR(fresnel(1.0).s, 0.4382591473903548, tol);
  EXPECT_NEAR(fresnel(0.5).c, 0.4923442258714464, tol);
  EXPECT_NEAR(fresnel(0.5).s, 0.0647324328600150, tol);
}

TEST(FresnelIntegrals, MatchMpmathOnBothSidesOfTheSwitch) {
  // C and S: 1e-13 (absolute where |value| < 1); f and g: 1e-13 relative (g is computed
  // from the continued fraction with ~2e-14 relative error, f to ~1e-15).
  for (const Ref& r : refs) {
    SCOPED_TRACE(r.x);
    const auto cs = fresnel(r.x);
    EXPECT_LT(rel_err(cs.c, r.c), 1e-13);
    EXPECT_LT(rel_err(cs.s, r.s), 1e-13);
    const auto a = fresnel_aux(r.x);
    EXPECT_LT(rel_only(a.imag(), r.f), 1e-13);
    EXPECT_LT(rel_only(a.real(), r.g), 1e-13);
  }
}

TEST(FresnelIntegrals, TailKeepsRelativePrecisionAtLargeArguments) {
  // int_z^inf e^{i pi t^2/2} dt = (1/2 - C) + i (1/2 - S), reference mpmath at 50 digits at the
  // double nearest z. At z = 12345.678 the phase pi z^2/2 is 2.4e8 rad: reducing it naively in
  // double would cost ~3e-8 relative; with the exact reduction we ask 1e-12 relative (of |tail|).
  struct T {
    double z, re, im;
  };
  constexpr T tails[] = {
      {-3.0, 1.1057207892976856296, 0.9963129989673750361},
      {-1.5, 0.94526117603982153506, 1.1975049600820930131},
      {-0.7, 1.159652351904510359, 0.67213645786347742245},
      {0.7, -0.15965235190451035902, 0.32786354213652257755},
      {1.4999, 0.054646426993781138653, -0.19754320665599874235},
      {1.5, 0.054738823960178464935, -0.19750496008209301308},
      {4.2, -0.041719203163415131535, -0.06319888839661139866},
      {12.345, -0.015079981202912227708, 0.020914614121809134047},
      {333.3, -0.00094080372237607107488, 0.00016419931241588774641},
      {12345.678, -0.000023334695318030487969, -0.000010966329801445715868},
      {10000000.0, 1.0132118364233777144e-22, 3.1830988618379067154e-8},
  };
  for (const T& t : tails) {
    SCOPED_TRACE(t.z);
    const std::complex<double> ref{t.re, t.im};
    EXPECT_LT(std::abs(fresnel_tail(t.z) - ref) / std::abs(ref), 1e-12);
  }
}

TEST(FresnelIntegrals, OddSymmetryAndLimits) {
  // Oddness is exact by construction (tolerance 0); the limits are 1/2 within |tail| ~ 1/(pi x).
  for (double x : {1e-3, 0.3, 1.2, 1.5, 2.7, 9.1, 123.4}) {
    EXPECT_EQ(fresnel(-x).c, -fresnel(x).c) << x;
    EXPECT_EQ(fresnel(-x).s, -fresnel(x).s) << x;
  }
  constexpr double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(fresnel(inf).c, 0.5);
  EXPECT_EQ(fresnel(inf).s, 0.5);
  EXPECT_EQ(fresnel(-inf).c, -0.5);
  EXPECT_EQ(fresnel(-inf).s, -0.5);
  for (double x : {1e3, 1e6, 1e9}) {
    EXPECT_NEAR(fresnel(x).c, 0.5, 1.0 / (pi * x)) << x;
    EXPECT_NEAR(fresnel(x).s, 0.5, 1.0 / (pi * x)) << x;
  }
  EXPECT_TRUE(std::isnan(fresnel(std::nan("")).c));
  EXPECT_TRUE(std::isnan(fresnel_aux(std::nan("")).imag()));
  EXPECT_EQ(fresnel(0.0).c, 0.0);
  EXPECT_EQ(fresnel(0.0).s, 0.0);
}

TEST(FresnelIntegrals, AuxiliaryAsymptotes) {
  // f ~ 1/(pi z) - 3/(pi^3 z^5), g ~ 1/(pi^2 z^3) - 15/(pi^4 z^7) (A&S 7.3.27-28): at z >= 1e4 the
  // second terms are below 1e-16 relative, so the leading ones are the reference, to 1e-13.
  for (double z : {1e4, 1e6, 1e12, 1e149, 1e151, 1e300}) {
    SCOPED_TRACE(z);
    const auto a = fresnel_aux(z);
    EXPECT_LT(rel_only(a.imag() * pi * z, 1.0), 1e-13);
    if (z < 1e100) {
      EXPECT_LT(rel_only(a.real() * pi * pi * z * z * z, 1.0), 1e-13);
    } else {
      EXPECT_LT(a.real(), 1e-200);  // g ~ 1/(pi^2 z^3) underflows towards 0
    }
  }
}

TEST(FresnelIntegrals, ContinuousAcrossSeriesToContinuedFractionSwitch) {
  // Both methods are accurate to ~1e-15 where they meet, so the step across the switch is at
  // rounding level: tolerance 1e-14 (the functions' own change over one ulp is ~1e-16).
  const double hi = houle::detail::fresnel_series_limit;
  const double lo = std::nextafter(hi, 0.0);
  EXPECT_NEAR(fresnel(lo).c, fresnel(hi).c, 1e-14);
  EXPECT_NEAR(fresnel(lo).s, fresnel(hi).s, 1e-14);
  EXPECT_LT(std::abs(fresnel_aux(lo) - fresnel_aux(hi)), 1e-14);
  EXPECT_LT(std::abs(fresnel_tail(lo) - fresnel_tail(hi)), 1e-14);
  EXPECT_LT(std::abs(fresnel_tail(-lo) - fresnel_tail(-hi)), 1e-14);
}

TEST(FresnelIntegrals, RationalApproximationWithinAbramowitzStegunBound) {
  // A&S 7.3.32-33 state |error| <= 2e-3 for f and for g, z >= 0. Checked against the double
  // implementation (itself checked above) on a dense grid z in [0, 60].
  double worst = 0.0;
  for (int i = 0; i <= 60000; ++i) {
    const double z = i * 1e-3;
    const auto exact = fresnel_aux(z);
    const auto approx = fresnel_aux_fg(float(z));
    worst = std::max({worst, std::fabs(approx.real() - exact.real()), std::fabs(approx.imag() - exact.imag())});
  }
  std::printf("A&S 7.3.32-33 f/g: max |error| on [0, 60] = %.3e\n", worst);
  EXPECT_LE(worst, 2e-3);
  // And against the mpmath table directly.
  for (const Ref& r : refs) {
    const auto approx = fresnel_aux_fg(float(r.x));
    EXPECT_NEAR(approx.imag(), r.f, 2e-3) << r.x;
    EXPECT_NEAR(approx.real(), r.g, 2e-3) << r.x;
  }
}

}  // namespace
