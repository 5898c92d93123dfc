// Evaluates one wave through the installed library's dispatch; exits non-zero on a wrong answer.
#include <cmath>
#include <cstdio>

#include <houle/surface/gerstner.hpp>
#include <houle/runtime/isa.hpp>

int main() {
  const houle::GerstnerWave wave{1.0f, 0.0f, 0.5f, 0.3f, 0.0f, 0.0f, 0.0f};
  const auto frame = houle::make_gerstner_frame({&wave, 1}, 0.0);
  if (!frame) return 1;
  const float x = 1.0f, y = 0.0f;
  float h = 0, gx = 0, gy = 0;
  houle::gerstner_eval(frame.value(), &x, &y, 1, {&h, &gx, &gy});
  std::printf("consumer: ISA %s, h(1, 0) = %.6f\n", houle::isa_name(houle::active_isa()).data(), h);
  return std::fabs(h - 0.3f * std::sin(0.5f)) < 1e-6f ? 0 : 1;
}
