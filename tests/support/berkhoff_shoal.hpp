// The elliptic-shoal experiment of Berkhoff, Booy & Radder (1982) as a houle scene, and its 208
// measured amplitudes (tests/data/berkhoff1982_sections.csv, with their source). docs/physics.md 10.5.
// The tests and the accuracy sweeps (bench/accuracy) share it.
#pragma once
#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "houle/sim/dispersion.hpp"
#include "houle/sim/scene.hpp"

namespace houle_test {

inline constexpr double berkhoff_period = 1.0;          // s
inline constexpr double berkhoff_amplitude = 0.0232;    // m, incident, in the 0.45 m deep part
inline constexpr double berkhoff_deep = 0.45;           // m

/// The published floor: 0.45 m deep, then a 1:50 slope whose contours are turned 20 deg to the
/// crests, starting 5.82 m before the shoal's centre, and on it the elliptic shoal
/// (x'/3)^2 + (y'/4)^2 <= 1 raising the floor by 0.5 sqrt(1 - (x'/3.75)^2 - (y'/5)^2) - 0.3, in the
/// frame (x', y') of the slope (x' shoreward). Depths under 0.07 m (beyond the measured area) are held
/// there, as the basin's model in the published comparisons does.
inline double berkhoff_depth(double x, double y) {
  const double c = std::cos(20.0 * 3.14159265358979323846 / 180.0), s = std::sin(20.0 * 3.14159265358979323846 / 180.0);
  const double xr = x * c - y * s, yr = x * s + y * c;
  double depth = berkhoff_deep - (xr >= -5.82 ? (5.82 + xr) / 50.0 : 0.0);
  if ((xr / 3.0) * (xr / 3.0) + (yr / 4.0) * (yr / 4.0) <= 1.0) {
    depth -= -0.3 + 0.5 * std::sqrt(std::max(0.0, 1.0 - (xr / 3.75) * (xr / 3.75) - (yr / 5.0) * (yr / 5.0)));
  }
  return std::max(depth, 0.07);
}

/// The experiment as a scene: the floor as a height map (0.05 m cells), one sine train towards +x
/// whose amplitude in the 0.45 m deep part is the incident 23.2 mm.
inline houle::Scene berkhoff_scene(houle::WaveModelKind model) {
  houle::Scene s;
  s.domain = {-10.0, -10.0, 12.0, 10.0};
  houle::HeightMap map;
  map.cell = 0.05;
  map.origin = {s.domain.x_min, s.domain.y_min};
  map.nx = std::uint32_t(std::lround((s.domain.x_max - s.domain.x_min) / map.cell)) + 1;
  map.ny = std::uint32_t(std::lround((s.domain.y_max - s.domain.y_min) / map.cell)) + 1;
  for (std::uint32_t j = 0; j < map.ny; ++j) {
    for (std::uint32_t i = 0; i < map.nx; ++i) {
      map.depth.push_back(float(berkhoff_depth(map.origin.x + i * map.cell, map.origin.y + j * map.cell)));
    }
  }
  s.floor.height_map = std::move(map);
  houle::WaveTrain t;
  t.direction_deg = 0.0;
  t.period = berkhoff_period;
  const houle::LinearWave w = houle::linear_wave(2.0 * 3.14159265358979323846 / berkhoff_period, berkhoff_deep);
  t.amplitude = berkhoff_amplitude / houle::shoaling_coefficient(w.kh);
  t.steepness = 0.0;
  s.trains = {t};
  s.capillary.amplitude = 0.0;
  // Rays fine enough for the shoal (finer changes nothing: docs/physics.md 10.5).
  s.dwt.step = 0.1;
  s.dwt.insertion_distance = 0.25;
  s.wave_model.kind = model;
  return s;
}

struct BerkhoffPoint {
  int section;
  double x, y;      // m
  double relative;  // H / H0
};

/// The measurements from `data_dir`/berkhoff1982_sections.csv (comment lines, a header, then
/// section, x, y, amplitude in mm); empty if the file cannot be read.
inline std::vector<BerkhoffPoint> berkhoff_measurements(const std::string& data_dir) {
  std::vector<BerkhoffPoint> points;
  std::ifstream f(data_dir + "/berkhoff1982_sections.csv");
  bool header = true;
  for (std::string line; std::getline(f, line);) {
    if (line.empty() || line[0] == '#') continue;
    if (header) {
      header = false;
      continue;
    }
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream row(line);
    BerkhoffPoint p{};
    double amplitude_mm = 0.0;
    row >> p.section >> p.x >> p.y >> amplitude_mm;
    p.relative = amplitude_mm / (1000.0 * berkhoff_amplitude);
    points.push_back(p);
  }
  return points;
}

}  // namespace houle_test
