#include "shore/scenes/mesh_cases.h"

#include <algorithm>
#include <cmath>

#include "shore/core/det_math.h"
#include "shore/scenes/terrain_step_cases.h"

namespace shore::scenes {

std::unique_ptr<water::Surface> seed_water() {
  auto s = std::make_unique<water::Surface>(water::SurfaceSettings::paper());
  s->disturb(water::Disturbance::point_velocity(24.5, 24.5, 2.0, 2.0));
  for (int k = 0; k < 40; ++k) s->step(0.4);
  return s;
}

mesh::Camera seed_water_camera() {
  return {.position = {24.5, -20.0, 20.0}, .fov_y_deg = 60.0, .viewport_height = 1080};
}

namespace {

/// The rut's depth profile (m, negative down) across it, d metres from its centre line.
double rut_profile(double d) {
  const double a = std::abs(d);
  if (a < 0.125) return -0.03 * (1.0 - det::pow(a / 0.125, 4.0));               // rounded walls
  if (a < 0.2) return 0.01 * det::sin(det::detail::kPi * (a - 0.125) / 0.075);  // berms
  return 0.0;
}

/// Deterministic roughness in [-1, 1] from a column's indices.
double roughness(std::int64_t i, std::int64_t j) {
  std::uint64_t h =
      static_cast<std::uint64_t>(i) * 0x9e3779b97f4a7c15ull ^ static_cast<std::uint64_t>(j) * 0xc2b2ae3d27d4eb4full;
  h ^= h >> 31;
  h *= 0xbf58476d1ce4e5b9ull;
  h ^= h >> 29;
  return static_cast<double>(h % 2001) / 1000.0 - 1.0;
}

}  // namespace

LargeField large_field(double side_m, double rut_m) {
  terrain::TerrainSettings s;
  s.cell = 0.01;
  s.material = terrain::Material::sand();
  LargeField f;
  f.soil = std::make_unique<terrain::Terrain>(s);
  const std::int64_t n = std::llround(side_m / s.cell) + 1;
  f.region = {0, 0, static_cast<int>(n), static_cast<int>(n)};
  f.rut_x0 = 0.5 * (side_m - rut_m);
  f.rut_x1 = f.rut_x0 + rut_m;
  f.rut_y = 0.5 * side_m;
  const std::int64_t i0 = f.soil->column_i(f.rut_x0), i1 = f.soil->column_i(f.rut_x1);
  const std::int64_t j0 = f.soil->column_j(f.rut_y - 0.2), j1 = f.soil->column_j(f.rut_y + 0.2);
  for (std::int64_t j = j0; j <= j1; ++j) {
    const double d = f.soil->column_y(j) - f.rut_y;
    for (std::int64_t i = i0; i <= i1; ++i) {
      const double x = f.soil->column_x(i);
      const double tread =
          std::abs(d) < 0.125 ? -0.002 * (0.5 + 0.5 * det::cos(2.0 * det::detail::kPi * x / 0.05)) : 0.0;
      f.soil->set_height(i, j, rut_profile(d) + tread + 0.0005 * roughness(i, j));
    }
  }
  return f;
}

mesh::Camera large_field_camera(const LargeField& f) {
  return {.position = {0.5 * (f.rut_x0 + f.rut_x1), f.rut_y, 2.0}, .fov_y_deg = 60.0, .viewport_height = 1080};
}

RollingWheel::RollingWheel(terrain::Terrain& soil, double x0, double y, double speed, double substep)
    : soil_(&soil), x_(x0), y_(y), speed_(speed), substep_(substep) {}

void RollingWheel::step() {
  constexpr double kRadius = 0.3, kWidth = 0.25, kSinkage = 0.03;
  const EnvelopeRaster env = wheel_envelope(*soil_, x_, kRadius - kSinkage, kRadius, kWidth, kRadius, y_);
  const terrain::Imprint im{&env, 0.0, true, {speed_, 0.0, 0.0}};
  soil_->step({&im, 1});
  x_ += speed_ * substep_;
}

}  // namespace shore::scenes
