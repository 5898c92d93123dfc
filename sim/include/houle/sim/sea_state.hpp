// A sea state as a sum of trains (docs/physics.md 2.9): a JONSWAP frequency spectrum with cos-2s
// directional spreading, expanded into a fixed number of components, each a WaveTrain that the effect
// plan, the tracer and the sea surface treat as any other.
//
// The expansion is deterministic, the same on every machine (no standard-library random
// distribution, whose results differ between libraries): the band [0.5, 5] fp is cut into
// `components` bins of equal energy, each a train at its bin's energy centroid with amplitude
// sqrt(2 m0 / N) (so sum a^2 / 2 = m0 = Hs^2 / 16); the direction quantiles (j + 0.5) / N of the
// cos-2s distribution are dealt to the bins in the order of a golden-ratio sequence (every direction
// used once, no correlation of direction with frequency), and the phases come from a fixed hash of
// (seed, sea state, component).
#pragma once
#include <cstddef>
#include <vector>

#include "houle/runtime/expected.hpp"
#include "houle/sim/scene.hpp"

namespace houle {

/// The JONSWAP variance density of a sea state, whose variance over all frequencies is Hs^2 / 16:
/// S(f) = C f^-5 exp(-5/4 (fp/f)^4) gamma^r(f), r = exp(-(f - fp)^2 / (2 sigma^2 fp^2)), sigma 0.07
/// below fp and 0.09 above, C from the integral (computed once, here). With gamma = 1 it is
/// Pierson-Moskowitz, 5/16 Hs^2 fp^4 f^-5 exp(-5/4 (fp/f)^4).
class JonswapSpectrum {
 public:
  explicit JonswapSpectrum(const SeaState& s) noexcept;
  /// m^2/Hz at frequency f (Hz).
  double density(double f) const noexcept;

 private:
  double fp_, gamma_, scale_;
};

/// The exponent s of the cos-2s distribution D(theta) ~ cos^{2s}(theta / 2) whose circular spread
/// sqrt(2 (1 - |E e^{i theta}|)) is spread_rad: s = 2 / spread_rad^2 - 1.
double cos2s_exponent(double spread_rad) noexcept;

/// The trains of sea state `index` of a scene (their sea_state member is `index`), in increasing
/// frequency; an error naming sea_states[index] when a component would break (its amplitude over the
/// Stokes limit 0.071 L0). The sea state's keys must be in their ranges.
Expected<std::vector<WaveTrain>> sea_state_components(const SeaState& s, std::size_t index);

}  // namespace houle
