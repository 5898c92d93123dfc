#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "houle/runtime/isa.hpp"
#include "houle/render/optics.hpp"
#include "ulp.hpp"
#include "angles.hpp"
#include "test_vectors.hpp"

namespace {

using Vec = std::array<double, 3>;
using houle_test::deg;
constexpr float n_water = houle::water_refractive_index;

double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const Vec& a) { return std::sqrt(dot(a, a)); }
Vec to_d(const std::array<float, 3>& v) { return {v[0], v[1], v[2]}; }

std::array<float, 3> random_unit(std::mt19937& rng) {
  std::normal_distribution<double> g;
  Vec v{g(rng), g(rng), g(rng)};
  const double n = norm(v);
  return {float(v[0] / n), float(v[1] / n), float(v[2] / n)};
}

// Transmittance from the Fresnel transmission amplitudes, independent of eq. 11's reflection terms:
// T = (n2 cos_t) / (n1 cos_i) (t_s^2 + t_p^2) / 2.
double fresnel_transmittance(double c, double n1, double n2) {
  const double s2 = (n1 / n2) * (n1 / n2) * (1.0 - c * c);
  if (s2 >= 1.0) return 0.0;
  const double ct = std::sqrt(1.0 - s2);
  const double ts = 2.0 * n1 * c / (n1 * c + n2 * ct), tp = 2.0 * n1 * c / (n2 * c + n1 * ct);
  return n2 * ct / (n1 * c) * 0.5 * (ts * ts + tp * tp);
}

// Stated tolerance of every SIMD path against the scalar reference: the kernels use only +, -, *,
// simd::div and simd::sqrt (correctly rounded on x86-64 and AArch64) without contraction, so the bits
// are identical. ARMv7 NEON divides and takes square roots by estimate plus Newton steps: a few ulp,
// and an absolute 1e-6 where a component is a difference of nearly equal numbers.
std::int64_t optics_ulp_tolerance(houle::Isa isa) { return isa == houle::Isa::neon ? 64 : 0; }
float simd_abs_tolerance(houle::Isa isa) { return isa == houle::Isa::neon ? 1e-6f : 0.0f; }

const std::vector<std::size_t> sizes = {0, 1, 2, 3, 5, 7, 8, 9, 15, 16, 17, 8 * 5 + 3, 8 * 37 + 3, 16 * 20 + 3, 1000};

TEST(Fresnel, MatchesTestVectorsBothDirections) {
  const TestVectors vectors = read_test_vectors("fresnel_water.csv");
  const std::vector<std::string>& header = vectors.header;
  const auto rows = numeric_rows(vectors);
  ASSERT_EQ(rows.size(), 91u);
  ASSERT_EQ(header[1], "R_air_to_water");
  ASSERT_EQ(header[3], "R_water_to_air");
  double worst_in = 0.0, worst_out = 0.0;
  for (const auto& r : rows) {
    const float c = float(std::cos(r[0] * deg));
    const float into = houle::fresnel_reflectance(c, 1.0f, n_water);
    const float out_of = houle::fresnel_reflectance(c, n_water, 1.0f);
    EXPECT_NEAR(into, r[1], 1e-6) << "air to water at " << r[0] << " deg";
    EXPECT_NEAR(out_of, r[3], 1e-6) << "water to air at " << r[0] << " deg";
    worst_in = std::max(worst_in, std::fabs(into - r[1]));
    worst_out = std::max(worst_out, std::fabs(out_of - r[3]));
  }
  std::printf("fresnel vs fresnel_water.csv: max |error| air->water %.2e, water->air %.2e\n", worst_in, worst_out);
}

TEST(Fresnel, ReflectanceAndTransmittanceSumToOne) {
  // K_r + K_t = 1 with K_t from the transmission amplitudes (energy conservation), both directions.
  double worst = 0.0;
  for (int i = 0; i <= 2000; ++i) {
    const double c = i / 2000.0;
    for (const auto& [n1, n2] : {std::pair{1.0, double(n_water)}, std::pair{double(n_water), 1.0}}) {
      const float r = houle::fresnel_reflectance(float(c), float(n1), float(n2));
      const double t = fresnel_transmittance(float(c), n1, n2);
      if (t == 0.0) {
        EXPECT_EQ(r, 1.0f);
      } else {
        worst = std::max(worst, std::fabs(r + t - 1.0));
      }
    }
  }
  EXPECT_LE(worst, 2e-6);
  std::printf("fresnel: max |K_r + K_t - 1| = %.2e\n", worst);
}

TEST(Fresnel, NormalIncidence) {
  // ((n - 1) / (n + 1))^2 = 0.021112 for n = 1.34, from either side.
  const double f0 = std::pow((1.34 - 1.0) / (1.34 + 1.0), 2.0);
  EXPECT_NEAR(houle::fresnel_reflectance(1.0f, 1.0f, n_water), f0, 1e-7);
  EXPECT_NEAR(houle::fresnel_reflectance(1.0f, n_water, 1.0f), f0, 1e-7);
  EXPECT_NEAR(houle::fresnel_reflectance(1.0f, 1.0f, n_water), 0.0211, 5e-5);
}

TEST(Fresnel, TotalInternalReflectionBeyond48_27DegreesFromBelow) {
  // Bisect for the first angle with R = 1 from the water side: asin(1 / 1.34) = 48.268 deg.
  double lo = 40.0, hi = 60.0;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (houle::fresnel_reflectance(float(std::cos(mid * deg)), n_water, 1.0f) == 1.0f ? hi : lo) = mid;
  }
  EXPECT_NEAR(hi, 48.27, 0.005);
  EXPECT_NEAR(hi, std::asin(1.0 / 1.34) / deg, 1e-4);
  std::printf("fresnel: total internal reflection from %.4f deg (asin(1/1.34) = %.4f)\n", hi,
              std::asin(1.0 / 1.34) / deg);
  // Never a NaN, for any cosine (clamped to [0, 1]) and both directions; grazing is a mirror either way.
  for (int i = -200; i <= 1200; ++i) {
    const float c = float(i) / 1000.0f;
    for (float eta : {1.0f / n_water, n_water}) {
      const float r = houle::fresnel_reflectance(c, eta, 1.0f);
      EXPECT_TRUE(r >= 0.0f && r <= 1.0f) << "cos " << c << " eta " << eta << " R " << r;
    }
  }
  EXPECT_EQ(houle::fresnel_reflectance(0.0f, 1.0f, n_water), 1.0f);
  EXPECT_EQ(houle::fresnel_reflectance(0.0f, n_water, 1.0f), 1.0f);
}

TEST(Fresnel, EveryIsaMatchesScalarIncludingTails) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> cosine(-0.2f, 1.2f);
  for (houle::Isa isa : houle::supported_isas()) {
    if (isa == houle::Isa::scalar) continue;
    std::int64_t worst = 0;
    for (float eta : {1.0f / n_water, n_water, 1.0f / 1.33f, 1.0f}) {
      for (std::size_t n : sizes) {
        std::vector<float> c(n), ref(n, -7.0f), got(n, -7.0f);
        for (float& v : c) v = cosine(rng);
        houle::fresnel_reflectance(houle::Isa::scalar, c.data(), eta, ref.data(), n);
        houle::fresnel_reflectance(isa, c.data(), eta, got.data(), n);
        for (std::size_t i = 0; i < n; ++i) {
          EXPECT_EQ(ref[i], houle::fresnel_reflectance(c[i], eta, 1.0f));  // batch scalar == scalar API
          if (std::fabs(ref[i] - got[i]) > simd_abs_tolerance(isa)) {
            worst = std::max(worst, houle::test::ulp_distance(ref[i], got[i]));
          }
        }
      }
    }
    EXPECT_LE(worst, optics_ulp_tolerance(isa)) << "ISA " << houle::isa_name(isa);
    std::printf("fresnel %s vs scalar: max %lld ulp (tolerance %lld)\n", houle::isa_name(isa).data(),
                static_cast<long long>(worst), static_cast<long long>(optics_ulp_tolerance(isa)));
  }
}

TEST(ReflectRefract, MirrorSnellAndUnitLength) {
  std::mt19937 rng(5);
  double worst_len = 0.0, worst_snell = 0.0, worst_mirror = 0.0;
  for (int k = 0; k < 20000; ++k) {
    const auto i_f = random_unit(rng), n_f = random_unit(rng);
    const auto rr = houle::reflect_refract(i_f, n_f);
    const Vec i = to_d(i_f);
    Vec n = to_d(n_f);
    const bool outside = dot(n, i) <= 0.0;
    EXPECT_EQ(rr.from_outside, outside);
    if (!outside) n = {-n[0], -n[1], -n[2]};  // the normal on the ray's side
    const double c = -dot(n, i), eta = outside ? 1.0 / 1.34 : 1.34;
    EXPECT_NEAR(rr.cos_i, c, 1e-6);
    EXPECT_EQ(rr.reflectance, houle::fresnel_reflectance(rr.cos_i, outside ? 1.0f : n_water, outside ? n_water : 1.0f));
    // Mirror: R = I + 2cN, on the incident side.
    const Vec r = to_d(rr.reflected);
    const Vec mirror{i[0] + 2 * c * n[0], i[1] + 2 * c * n[1], i[2] + 2 * c * n[2]};
    worst_len = std::max(worst_len, std::fabs(norm(r) - 1.0));
    for (int a = 0; a < 3; ++a) worst_mirror = std::max(worst_mirror, std::fabs(r[a] - mirror[a]));
    const bool tir = eta * eta * (1.0 - c * c) >= 1.0;
    if (std::fabs(eta * eta * (1.0 - c * c) - 1.0) < 1e-5) continue;  // float may decide either way
    ASSERT_EQ(rr.total_internal_reflection, tir);
    const Vec t = to_d(rr.refracted);
    if (tir) {
      EXPECT_EQ(norm(t), 0.0);
      EXPECT_EQ(rr.reflectance, 1.0f);
      continue;
    }
    // Snell: |T x N| = eta |I x N|, T in the plane of I and N, on the far side, unit length.
    worst_len = std::max(worst_len, std::fabs(norm(t) - 1.0));
    worst_snell = std::max(worst_snell, std::fabs(norm(cross(t, n)) - eta * norm(cross(i, n))));
    EXPECT_NEAR(dot(t, cross(i, n)), 0.0, 1e-5);
    EXPECT_LE(dot(t, n), 0.0);
    EXPECT_NEAR(-dot(t, n), rr.cos_t, 2e-6);
  }
  EXPECT_LE(worst_len, 3e-7);
  EXPECT_LE(worst_snell, 2e-6);
  EXPECT_LE(worst_mirror, 1e-6);
  std::printf("reflect_refract: max |len - 1| %.1e, Snell error %.1e, mirror error %.1e\n", worst_len, worst_snell,
              worst_mirror);
}

TEST(ReflectRefract, FromBelowSnellsWindowAndTotalInternalReflection) {
  const std::array<float, 3> up{0.0f, 0.0f, 1.0f};
  for (double theta = 0.0; theta < 90.0; theta += 0.25) {
    // Under water, looking up at angle theta from the vertical.
    const std::array<float, 3> i{float(std::sin(theta * deg)), 0.0f, float(std::cos(theta * deg))};
    const auto rr = houle::reflect_refract(i, up);
    EXPECT_FALSE(rr.from_outside);
    EXPECT_LT(rr.reflected[2], 0.0f) << theta;  // reflected back down into the water
    if (theta < 48.2) {
      EXPECT_FALSE(rr.total_internal_reflection) << theta;
      EXPECT_GT(rr.refracted[2], 0.0f);
      EXPECT_NEAR(rr.refracted[0], 1.34 * std::sin(theta * deg), 2e-6) << theta;
      EXPECT_LT(rr.reflectance, 1.0f);
    } else if (theta > 48.3) {
      EXPECT_TRUE(rr.total_internal_reflection) << theta;
      EXPECT_EQ(rr.reflectance, 1.0f);
      EXPECT_EQ(rr.refracted, (std::array<float, 3>{0.0f, 0.0f, 0.0f}));
    }
  }
  // Grazing along the surface, from either side: finite, unit reflection.
  for (float nz : {1.0f, -1.0f}) {
    const auto rr = houle::reflect_refract({1.0f, 0.0f, 0.0f}, {0.0f, 0.0f, nz});
    EXPECT_EQ(rr.reflected, (std::array<float, 3>{1.0f, 0.0f, 0.0f}));
    EXPECT_EQ(rr.reflectance, 1.0f);
  }
}

TEST(ReflectRefract, EveryIsaMatchesScalarIncludingTails) {
  std::mt19937 rng(23);
  for (houle::Isa isa : houle::supported_isas()) {
    if (isa == houle::Isa::scalar) continue;
    std::int64_t worst = 0;
    for (const auto& [n_out, n_in] : {std::pair{1.0f, n_water}, std::pair{n_water, 1.0f}}) {
      for (std::size_t n : sizes) {
        std::vector<float> in[6], ref[7], got[7];
        for (auto& v : in) v.resize(n);
        for (auto& v : ref) v.assign(n, -7.0f);
        for (auto& v : got) v.assign(n, -7.0f);
        for (std::size_t k = 0; k < n; ++k) {
          const auto i = random_unit(rng), nn = random_unit(rng);
          for (int a = 0; a < 3; ++a) in[a][k] = i[a], in[3 + a][k] = nn[a];
        }
        const houle::ReflectRefractInput input{in[0].data(), in[1].data(), in[2].data(),
                                               in[3].data(), in[4].data(), in[5].data()};
        const auto view = [](std::vector<float>(&o)[7]) {
          return houle::ReflectRefractOutput{o[0].data(), o[1].data(), o[2].data(), o[3].data(),
                                            o[4].data(), o[5].data(), o[6].data()};
        };
        houle::reflect_refract(houle::Isa::scalar, input, n, n_out, n_in, view(ref));
        houle::reflect_refract(isa, input, n, n_out, n_in, view(got));
        for (std::size_t k = 0; k < n; ++k) {
          // The batch scalar path is the scalar API.
          const auto one = houle::reflect_refract({in[0][k], in[1][k], in[2][k]}, {in[3][k], in[4][k], in[5][k]},
                                                  n_out, n_in);
          EXPECT_EQ(ref[0][k], one.reflected[0]);
          EXPECT_EQ(ref[5][k], one.refracted[2]);
          EXPECT_EQ(ref[6][k], one.reflectance);
          for (int a = 0; a < 7; ++a) {
            if (std::fabs(ref[a][k] - got[a][k]) > simd_abs_tolerance(isa)) {
              worst = std::max(worst, houle::test::ulp_distance(ref[a][k], got[a][k]));
            }
          }
        }
      }
    }
    EXPECT_LE(worst, optics_ulp_tolerance(isa)) << "ISA " << houle::isa_name(isa);
    std::printf("reflect_refract %s vs scalar: max %lld ulp (tolerance %lld)\n", houle::isa_name(isa).data(),
                static_cast<long long>(worst), static_cast<long long>(optics_ulp_tolerance(isa)));
  }
}

// Rows as the renderer's shading sees them: sea hits from above and below and no hit, gradients up
// to steep, rays looking every way (some away from the normal, which bends it).
struct SeaRow {
  std::vector<float> side, gx, gy, dx, dy, dz;
};
SeaRow random_sea_row(std::mt19937& rng, std::size_t n) {
  SeaRow r;
  std::uniform_int_distribution<int> side(-1, 1);
  std::normal_distribution<float> slope(0.0f, 0.6f);
  for (std::size_t k = 0; k < n; ++k) {
    const auto d = random_unit(rng);
    r.side.push_back(float(side(rng)));
    r.gx.push_back(k % 7 == 3 ? 0.0f : slope(rng));
    r.gy.push_back(k % 5 == 1 ? -0.0f : slope(rng));
    r.dx.push_back(d[0]);
    r.dy.push_back(d[1]);
    r.dz.push_back(d[2]);
  }
  return r;
}

// The stated tolerance of the row kernels against the scalar path over the given arrays: optics_ulp_tolerance.
std::int64_t worst_ulp(houle::Isa isa, const std::vector<std::vector<float>>& ref, const std::vector<std::vector<float>>& got) {
  std::int64_t worst = 0;
  for (std::size_t a = 0; a < ref.size(); ++a) {
    for (std::size_t k = 0; k < ref[a].size(); ++k) {
      if (std::fabs(ref[a][k] - got[a][k]) > simd_abs_tolerance(isa) || std::isnan(got[a][k])) {
        worst = std::max(worst, houle::test::ulp_distance(ref[a][k], got[a][k]));
      }
    }
  }
  return worst;
}

void expect_within_tolerance(const char* kernel, houle::Isa isa, std::int64_t worst) {
  EXPECT_LE(worst, optics_ulp_tolerance(isa)) << kernel << " on " << houle::isa_name(isa);
  std::printf("%s %s vs scalar: max %lld ulp (tolerance %lld)\n", kernel, houle::isa_name(isa).data(),
              static_cast<long long>(worst), static_cast<long long>(optics_ulp_tolerance(isa)));
}

TEST(SeaNormals, UnitBentTowardsTheRayAndUpWithoutAHit) {
  std::mt19937 rng(41);
  const std::size_t n = 8 * 50 + 3;
  const SeaRow row = random_sea_row(rng, n);
  std::vector<float> nx(n), ny(n), nz(n);
  houle::sea_normals({row.side.data(), row.gx.data(), row.gy.data(), row.dx.data(), row.dy.data(), row.dz.data()}, n,
                     {nx.data(), ny.data(), nz.data()});
  int bent = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const Vec nn{nx[k], ny[k], nz[k]}, d{row.dx[k], row.dy[k], row.dz[k]};
    if (row.side[k] == 0.0f) {
      EXPECT_EQ(nn, (Vec{0.0, 0.0, 1.0}));
      continue;
    }
    EXPECT_NEAR(norm(nn), 1.0, 1e-6);
    // The ray meets the normal head on from above (N.d < 0), the other way from below: where the
    // plain normal does not, it is bent to N.d = -0.01 (+0.01) along d and renormalised.
    const double nd = dot(nn, d), want = row.side[k] > 0.0f ? -0.01 : 0.01;
    EXPECT_LT(row.side[k] > 0.0f ? nd : -nd, 0.0);
    const Vec plain{-row.gx[k] / norm({row.gx[k], row.gy[k], 1.0}), -row.gy[k] / norm({row.gx[k], row.gy[k], 1.0}),
                    1.0 / norm({row.gx[k], row.gy[k], 1.0})};
    const double plain_nd = dot(plain, d);
    Vec expect = plain;
    if (row.side[k] > 0.0f ? plain_nd > want : plain_nd < want) {
      ++bent;
      for (int a = 0; a < 3; ++a) expect[a] = plain[a] - (plain_nd - want) * d[a];
      const double len = norm(expect);
      for (double& c : expect) c /= len;
    }
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(nn[a], expect[a], 1e-5);
  }
  EXPECT_GT(bent, 20);  // the rows do exercise the bend
}

TEST(SeaNormals, EveryIsaMatchesScalarIncludingTails) {
  std::mt19937 rng(42);
  for (houle::Isa isa : houle::supported_isas()) {
    if (isa == houle::Isa::scalar) continue;
    std::int64_t worst = 0;
    for (std::size_t n : sizes) {
      const SeaRow row = random_sea_row(rng, n);
      std::vector<std::vector<float>> ref(3, std::vector<float>(n, -7.0f)), got = ref;
      const houle::SeaNormalsInput in{row.side.data(), row.gx.data(), row.gy.data(), row.dx.data(), row.dy.data(), row.dz.data()};
      houle::sea_normals(houle::Isa::scalar, in, n, {ref[0].data(), ref[1].data(), ref[2].data()});
      houle::sea_normals(isa, in, n, {got[0].data(), got[1].data(), got[2].data()});
      worst = std::max(worst, worst_ulp(isa, ref, got));
    }
    expect_within_tolerance("sea_normals", isa, worst);
  }
}

// Reflected and refracted rays of random rows, with rays grazing or below the horizon and straight down.
struct AirRow {
  SeaRow sea;
  std::vector<float> r[3], t[3];
};
AirRow random_air_row(std::mt19937& rng, std::size_t n) {
  AirRow row{random_sea_row(rng, n), {}, {}};
  std::uniform_real_distribution<float> low(-0.05f, 0.05f);
  for (std::size_t k = 0; k < n; ++k) {
    auto r = random_unit(rng), t = random_unit(rng);
    if (k % 4 == 1) r = {r[0], r[1], low(rng)};  // near the horizon, not unit: renormalised all the same
    if (k % 9 == 2) r = {0.0f, 0.0f, -1.0f};
    if (k % 11 == 5) t = {0.0f, 0.0f, 0.0f};  // total internal reflection
    for (int a = 0; a < 3; ++a) row.r[a].push_back(r[a]), row.t[a].push_back(t[a]);
  }
  return row;
}
houle::AirDirectionsInput air_input(const AirRow& row) {
  return {row.sea.side.data(), row.sea.dx.data(), row.sea.dy.data(), row.sea.dz.data(), row.r[0].data(),
          row.r[1].data(),     row.r[2].data(),   row.t[0].data(),   row.t[1].data(),   row.t[2].data()};
}

TEST(AirDirections, ReflectedAboveRefractedBelowLiftedOverTheHorizon) {
  std::mt19937 rng(43);
  const std::size_t n = 8 * 50 + 3;
  constexpr float min_dz = 0.01f;
  const AirRow row = random_air_row(rng, n);
  std::vector<float> x(n), y(n), z(n);
  houle::air_directions(air_input(row), n, min_dz, {x.data(), y.data(), z.data()});
  int lifted = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const float side = row.sea.side[k];
    const Vec got{x[k], y[k], z[k]};
    const std::vector<float>* src = side > 0.0f ? row.r : side < 0.0f ? row.t : nullptr;
    if (src == nullptr) {
      EXPECT_EQ(got, (Vec{row.sea.dx[k], row.sea.dy[k], row.sea.dz[k]}));
      continue;
    }
    const Vec v{src[0][k], src[1][k], src[2][k]};
    if (v[2] >= min_dz) {
      EXPECT_EQ(got, v);
      continue;
    }
    ++lifted;
    const double h = std::hypot(v[0], v[1]);
    if (h == 0.0) {
      EXPECT_EQ(got, (Vec{0.0, 0.0, 1.0}));  // straight down (or no ray): straight up
      continue;
    }
    // The same azimuth, z = min_dz, unit.
    EXPECT_FLOAT_EQ(float(got[2]), min_dz);
    EXPECT_NEAR(norm(got), 1.0, 1e-6);
    EXPECT_NEAR(got[0] * v[1] - got[1] * v[0], 0.0, 1e-6);
    EXPECT_GT(got[0] * v[0] + got[1] * v[1], 0.0);
  }
  EXPECT_GT(lifted, 50);
}

TEST(AirDirections, EveryIsaMatchesScalarIncludingTails) {
  std::mt19937 rng(44);
  for (houle::Isa isa : houle::supported_isas()) {
    if (isa == houle::Isa::scalar) continue;
    std::int64_t worst = 0;
    for (std::size_t n : sizes) {
      const AirRow row = random_air_row(rng, n);
      std::vector<std::vector<float>> ref(3, std::vector<float>(n, -7.0f)), got = ref;
      houle::air_directions(houle::Isa::scalar, air_input(row), n, 0.01f, {ref[0].data(), ref[1].data(), ref[2].data()});
      houle::air_directions(isa, air_input(row), n, 0.01f, {got[0].data(), got[1].data(), got[2].data()});
      worst = std::max(worst, worst_ulp(isa, ref, got));
    }
    expect_within_tolerance("air_directions", isa, worst);
  }
}

}  // namespace
