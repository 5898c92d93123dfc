#include "pade_factors.hpp"

#include <algorithm>
#include <cmath>

namespace houle::detail {
namespace {

/// Solves a x = b (n x n, row-major) by Gaussian elimination with partial pivoting.
std::vector<cplx> solve(std::vector<cplx> a, std::vector<cplx> b) {
  const std::size_t n = b.size();
  for (std::size_t c = 0; c < n; ++c) {
    std::size_t pivot = c;
    for (std::size_t r = c + 1; r < n; ++r) {
      if (std::abs(a[r * n + c]) > std::abs(a[pivot * n + c])) pivot = r;
    }
    for (std::size_t k = 0; k < n; ++k) std::swap(a[c * n + k], a[pivot * n + k]);
    std::swap(b[c], b[pivot]);
    for (std::size_t r = c + 1; r < n; ++r) {
      const cplx f = a[r * n + c] / a[c * n + c];
      for (std::size_t k = c; k < n; ++k) a[r * n + k] -= f * a[c * n + k];
      b[r] -= f * b[c];
    }
  }
  std::vector<cplx> x(n);
  for (std::size_t r = n; r-- > 0;) {
    cplx s = b[r];
    for (std::size_t k = r + 1; k < n; ++k) s -= a[r * n + k] * x[k];
    x[r] = s / a[r * n + r];
  }
  return x;
}

cplx horner(const std::vector<cplx>& c, cplx z) {
  cplx v = 0.0;
  for (std::size_t i = c.size(); i-- > 0;) v = v * z + c[i];
  return v;
}

/// The roots of c_0 + c_1 z + ... + c_d z^d (c_d != 0): Durand-Kerner from fixed starting points
/// (deterministic), then Newton steps on the polynomial itself.
std::vector<cplx> roots(const std::vector<cplx>& c) {
  const std::size_t d = c.size() - 1;
  std::vector<cplx> monic(c.size());
  for (std::size_t i = 0; i <= d; ++i) monic[i] = c[i] / c[d];
  double radius = 0.0;  // Cauchy's bound
  for (std::size_t i = 0; i < d; ++i) radius = std::max(radius, std::abs(monic[i]));
  radius += 1.0;
  std::vector<cplx> z(d);
  cplx w = 1.0;
  for (std::size_t i = 0; i < d; ++i, w *= cplx(0.4, 0.9)) z[i] = radius * w / std::abs(w) * 0.5;
  for (int iter = 0; iter < 500; ++iter) {
    double change = 0.0;
    for (std::size_t i = 0; i < d; ++i) {
      cplx den = 1.0;
      for (std::size_t j = 0; j < d; ++j) {
        if (j != i) den *= z[i] - z[j];
      }
      const cplx step = horner(monic, z[i]) / den;
      z[i] -= step;
      change = std::max(change, std::abs(step) / (1.0 + std::abs(z[i])));
    }
    if (change < 1e-15) break;
  }
  std::vector<cplx> derivative(d);
  for (std::size_t i = 1; i <= d; ++i) derivative[i - 1] = double(i) * monic[i];
  for (cplx& r : z) {
    for (int iter = 0; iter < 3; ++iter) {
      const cplx slope = horner(derivative, r);
      if (std::abs(slope) == 0.0) break;
      r -= horner(monic, r) / slope;
    }
  }
  return z;
}

/// A polynomial in Y as c * prod (1 + f_j X) with 1 + X = e^{i alpha}(1 + Y): each root r gives
/// Y - r = (e^{-i alpha} - 1 - r) (1 + f X), f = e^{-i alpha} / (e^{-i alpha} - 1 - r).
cplx factor_in_x(const std::vector<cplx>& poly, double alpha, std::vector<cplx>& factors) {
  std::size_t degree = poly.size() - 1;
  double largest = 0.0;
  for (const cplx& v : poly) largest = std::max(largest, std::abs(v));
  while (degree > 0 && std::abs(poly[degree]) <= 1e-14 * largest) --degree;
  const std::vector<cplx> used(poly.begin(), poly.begin() + std::ptrdiff_t(degree) + 1);
  const cplx e = std::polar(1.0, -alpha);
  cplx c = used[degree];
  factors.clear();
  if (degree == 0) return c;
  for (const cplx& r : roots(used)) {
    const cplx d = e - 1.0 - r;
    c *= d;
    factors.push_back(e / d);
  }
  return c;
}

}  // namespace

cplx PadeFactors::operator()(cplx x) const noexcept {
  cplx v = scale;
  for (const cplx& a : num) v *= 1.0 + a * x;
  for (const cplx& b : den) v /= 1.0 + b * x;
  return v;
}

PadeFactors rotated_pade(std::span<const cplx> g, double alpha) {
  const std::size_t m = (g.size() - 1) / 2;
  // Denominator q (q_0 = 1): sum_{j=0..m} q_j g_{m+i-j} = 0 for i = 1..m.
  std::vector<cplx> a(m * m), b(m);
  for (std::size_t i = 1; i <= m; ++i) {
    for (std::size_t j = 1; j <= m; ++j) a[(i - 1) * m + (j - 1)] = g[m + i - j];
    b[i - 1] = -g[m + i];
  }
  std::vector<cplx> q(m + 1, 1.0);
  const std::vector<cplx> tail = solve(a, b);
  std::copy(tail.begin(), tail.end(), q.begin() + 1);
  std::vector<cplx> p(m + 1, 0.0);
  for (std::size_t i = 0; i <= m; ++i) {
    for (std::size_t j = 0; j <= i; ++j) p[i] += q[j] * g[i - j];
  }
  PadeFactors f;
  const cplx cp = factor_in_x(p, alpha, f.num);
  const cplx cq = factor_in_x(q, alpha, f.den);
  f.scale = cp / cq;
  return f;
}

std::vector<cplx> propagator_series(double sigma, double alpha, int n) {
  // h(Y) = i sigma (e^{i alpha/2} sqrt(1 + Y) - 1), then g = exp(h) by g' = h' g.
  const cplx rot = std::polar(1.0, 0.5 * alpha);
  std::vector<cplx> h(std::size_t(n) + 1), g(std::size_t(n) + 1);
  double binomial = 1.0;
  for (int k = 0; k <= n; ++k) {
    h[std::size_t(k)] = cplx(0.0, sigma) * rot * binomial;
    binomial *= (0.5 - k) / (k + 1);
  }
  h[0] = cplx(0.0, sigma) * (rot - 1.0);
  g[0] = std::exp(h[0]);
  for (int k = 1; k <= n; ++k) {
    cplx s = 0.0;
    for (int j = 1; j <= k; ++j) s += double(j) * h[std::size_t(j)] * g[std::size_t(k - j)];
    g[std::size_t(k)] = s / double(k);
  }
  return g;
}

std::vector<cplx> power_series(double p, double alpha, int n) {
  std::vector<cplx> g(std::size_t(n) + 1);
  cplx c = std::polar(1.0, alpha * p);
  for (int k = 0; k <= n; ++k) {
    g[std::size_t(k)] = c;
    c *= (p - k) / (k + 1);
  }
  return g;
}

}  // namespace houle::detail
