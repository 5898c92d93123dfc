#include "dispersion_table.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "houle/sim/dispersion.hpp"

namespace houle::detail {
namespace {

constexpr double u_max = 5.0;            // sqrt(25): deep enough that kh = k0h exactly
constexpr int per_unit = 1024;           // nodes per unit of u: h^4 / 384 x'''' ~ 1e-15
constexpr int nodes = int(u_max) * per_unit + 1;

struct Table {
  std::vector<double> x, dx;  // kh and d(kh)/du at u = i / per_unit
  Table() : x(nodes), dx(nodes) {
    for (int i = 0; i < nodes; ++i) {
      const double u = double(i) / per_unit;
      const double xi = i == 0 ? 0.0 : solve_kh(u * u);
      // dx/dy = 1 / (tanh x + x sech^2 x); dx/du = 2u dx/dy (-> 1 as u -> 0).
      const double t = std::tanh(xi);
      x[std::size_t(i)] = xi;
      dx[std::size_t(i)] = i == 0 ? 1.0 : 2.0 * u / (t + xi * (1.0 - t * t));
    }
  }
};

const Table& table() {
  static const Table t;  // built once, thread-safe
  return t;
}

}  // namespace

double kh_from_table(double y) noexcept {
  if (!(y > 0.0)) return 0.0;
  if (y >= u_max * u_max) return y;
  const Table& t = table();
  const double s = std::sqrt(y) * per_unit;
  const int i = std::min(int(s), nodes - 2);
  const double f = s - double(i), g = 1.0 - f;
  const std::size_t a = std::size_t(i), b = a + 1;
  const double h = 1.0 / per_unit;
  // Cubic Hermite on [u_i, u_i+1].
  return t.x[a] * g * g * (1.0 + 2.0 * f) + t.x[b] * f * f * (1.0 + 2.0 * g) + h * f * g * (t.dx[a] * g - t.dx[b] * f);
}

}  // namespace houle::detail
